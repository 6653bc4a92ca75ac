// vtou (paper §III-D): where a map voxel lies in the image of a frame, for the
// IoU of map instances with predicted masks. Free of the map so it can be
// checked by hand (tests/core/test_mask_footprint.cpp). Pixel centres are at
// integer image coordinates (u = fx x / z + cx), as in the forward projection.
#pragma once

#include <pndt/gaussian.h>
#include <pndt/types.h>

#include <algorithm>
#include <cmath>

namespace pndt
{
/// A candidate voxel in the image: pixel rows r0..r1 and columns c0..c1, within
/// them the pixel centres inside the projected Gaussian's ellipse (vtou) or,
/// without a Gaussian, the projected cube's box. Empty when r0 > r1.
struct MaskFootprint
{
    bool ellipse = false;
    int c0 = 0, c1 = -1, r0 = 0, r1 = -1;
    double u0 = 0, v0 = 0;              ///< ellipse centre (pixels)
    double s00 = 0, s01 = 0, s11 = 0;   ///< inverse of its 2x2 covariance
    double z0 = 0;                      ///< depth the pixels must agree with
};

/// The Gaussian projected to the image (J Sigma_cam J^T) and cut at Mahalanobis
/// distance^2 `k2`, clipped to the image; empty behind the camera.
MaskFootprint gaussianFootprint(const NdtGaussian& g, const Pose& T_cam_world, const CameraIntrinsics& K, double k2);

/// The bounding box of a cube (corner `min_corner`, edge `size`) in the image:
/// the pixels whose centres it covers, clipped; z0 is the depth of its centre.
MaskFootprint cubeFootprint(const Eigen::Vector3d& min_corner, double size, const Pose& T_cam_world,
                            const CameraIntrinsics& K);

/// A pixel coordinate from a double that may be far outside the image.
inline int clampedPixel(double x) { return int(std::max(-1.0e9, std::min(1.0e9, x))); }

/// Row r's columns [c0, c1] inside the footprint (the ellipse's chord, or the
/// box); false when the row has none. Inline: the vtou kernels call it per row.
inline bool footprintRow(const MaskFootprint& fp, int r, double k2, int& c0, int& c1)
{
    c0 = fp.c0;
    c1 = fp.c1;
    if (fp.ellipse)
    {
        // Pixel centres inside the ellipse: S00 du^2 + 2 S01 du dv + S11 dv^2 <= k2,
        // an interval of du per row.
        const double dv = r - fp.v0;
        const double qa = fp.s00, qb = 2 * fp.s01 * dv, qc = fp.s11 * dv * dv - k2;
        const double disc = qb * qb - 4 * qa * qc;
        if (!(disc >= 0) || !(qa > 0)) return false;
        const double root = std::sqrt(disc);
        c0 = std::max(c0, clampedPixel(std::ceil(fp.u0 + (-qb - root) / (2 * qa))));
        c1 = std::min(c1, clampedPixel(std::floor(fp.u0 + (-qb + root) / (2 * qa))));
    }
    return c0 <= c1;
}

/// Pixels [begin, end) of one image row in a thing voxel's vtou (footprint and
/// depth test passed), all of one predicted instance (frame index, -1 none).
struct MaskSpan
{
    uint32_t begin, end;
    int32_t predicted;
};

/// The depth test: a pixel belongs to the voxel only at about its depth.
inline bool agreesInDepth(const MaskFootprint& fp, float depth, double tolerance)
{
    return std::abs(double(depth) - fp.z0) <= tolerance;
}

}  // namespace pndt
