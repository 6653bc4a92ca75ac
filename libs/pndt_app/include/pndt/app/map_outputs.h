// Files that show what is in a map: instance report (JSON) and rendered views (PNG).
#pragma once

#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/panoptic_map.h>

#include <string>

namespace pndt::app
{
/// "What's in the map": instances grouped by class, each with id, voxel count,
/// centroid, extent and bounding box. Written atomically.
void writeInstanceReport(const PanopticMap& map, const std::string& path);

/// The map rendered from `T_world_cam` with intrinsics K. Writes, for prefix P:
///   P_semantic.png, P_instance.png, P_panoptic.png  — colour views (semantic and
///     panoptic with a class legend on the right);
///   P_panoptic_rgb8.png — evaluation encoding R = class, G<<8|B = instance;
///   P_semantic_label.png — 8-bit class ids (ScanNet 2D semantic format);
///   P_depth.png — 16-bit depth in millimetres.
void writeRenderedViews(const PanopticMap& map, const Pose& T_world_cam, const CameraIntrinsics& K,
                        const std::string& prefix);

/// The camera of overview pictures: 640x480 with a 60 degree view, whatever the frames' camera
/// (a 1x1 camera, or one whose principal point lies off the image, gave empty overviews).
inline CameraIntrinsics overviewIntrinsics() { return {640, 480, 554.3, 554.3, 319.5, 239.5}; }

/// The top-down semantic floor plan (map_pictures.h floorPlan) as PNG, atomically.
void writeFloorPlan(const PanopticMap& map, const std::string& path);

/// A 3D view of the voxels' exposed faces, coloured like the panoptic view and shaded
/// by face direction, rendered off-screen (no display needed): solid surfaces without
/// the inner faces and gaps of drawing each voxel as its own cube.
void writeMeshScreenshot(const PanopticNDTMap& map, const std::string& path, int width = 1024, int height = 768,
                         double azimuth_deg = -60, double elevation_deg = 35);

/// A 3D view of the map (its own getVisualizationInto, i.e. what MRPT viewers
/// show) rendered off-screen to a PNG, looking at the map's centre from the
/// given azimuth/elevation (degrees). Needs no display.
void writeScreenshot(const PanopticNDTMap& map, const std::string& path, int width = 1024, int height = 768,
                     double azimuth_deg = -60, double elevation_deg = 35);

/// Opens an interactive MRPT 3D window on the map and returns when it is
/// closed; false (without opening) when there is no display.
bool showInteractive(const PanopticNDTMap& map);

}  // namespace pndt::app
