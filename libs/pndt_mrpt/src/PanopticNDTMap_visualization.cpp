// 3D view of the map: points, NDT ellipsoids or cubes, coloured by label.
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/opengl/CEllipsoid3D.h>
#include <mrpt/opengl/COctoMapVoxels.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/mrpt/voxel_colors.h>

#include <algorithm>
#include <cmath>

namespace pndt
{
Rgb heightColor(double z)
{
    // Blue (low) -> green -> red (high) over 0..3 m: unlabelled geometry stays readable.
    const double t = std::clamp(z / 3.0, 0.0, 1.0);
    const double r = std::clamp(2.0 * t - 0.5, 0.0, 1.0), g = 1.0 - std::abs(2.0 * t - 1.0),
                 b = std::clamp(1.5 - 2.0 * t, 0.0, 1.0);
    return {uint8_t(55 + 200 * r), uint8_t(55 + 200 * g), uint8_t(55 + 200 * b)};
}

Rgb voxelColor(const PanopticMap& map, uint32_t voxel, ColorMode mode)
{
    const PanopticLabel pl = map.panopticLabel(voxel);
    const uint16_t semantic = map.semanticLabel(voxel);
    if (semantic == 0 && pl.semantic == 0 && pl.instance == 0)
    {
        return heightColor(map.pointOf(voxel).z());
    }
    switch (mode)
    {
        // A voxel without semantic evidence shows the class label_fill_distance gave it.
        case ColorMode::Semantic: return classColor(semantic != 0 ? semantic : pl.semantic);
        case ColorMode::Instance: return instanceColor(pl.instance);
        case ColorMode::Panoptic:
        default: return pl.instance != 0 ? instanceColor(pl.instance) : classColor(pl.semantic);
    }
}

void PanopticNDTMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& out) const
{
    if (!genericMapParams.enableSaveAs3DObject) return;
    map_.finalize();
    const auto& store = map_.voxels();
    const RenderOptions& ro = renderOptions;
    const double vs = map_.options().voxel_size;

    size_t occupied = 0;
    for (const Voxel& v : store.voxels()) occupied += map_.isOccupied(v);
    const bool ellipsoids = ro.shape == VoxelShape::Ellipsoids && occupied <= ro.max_ellipsoids;

    auto points = mrpt::opengl::CPointCloudColoured::Create();
    points->setPointSize(ro.point_size);
    auto cubes = mrpt::opengl::COctoMapVoxels::Create();
    cubes->resizeVoxelSets(2);
    cubes->showGridLines(false);
    auto free_points = mrpt::opengl::CPointCloudColoured::Create();
    free_points->setPointSize(1.0f);

    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e18), hi = -lo;
    for (uint32_t i = 0; i < store.size(); ++i)
    {
        const Voxel& v = store[i];
        const Eigen::Vector3d c = map_.grid().center(store.key(i));
        lo = lo.cwiseMin(c);
        hi = hi.cwiseMax(c);
        if (!map_.isOccupied(v))
        {
            if (ro.show_free && v.occ < 0) free_points->push_back(float(c.x()), float(c.y()), float(c.z()), .8f, .8f, .8f, .3f);
            continue;
        }
        const Rgb col = voxelColor(map_, i, ro.color_mode);
        const Eigen::Vector3d p = map_.pointOf(i);
        if (ellipsoids && map_.hasGaussian(v))
        {
            const NdtGaussian g = map_.gaussianOf(v);
            mrpt::math::CMatrixDouble33 cov;
            cov.asEigen() = g.cov;
            mrpt::math::CMatrixDouble31 mean;
            mean.asEigen() = g.mean;
            auto e = mrpt::opengl::CEllipsoid3D::Create();
            e->setCovMatrixAndMean(cov, mean);
            e->setQuantiles(float(ro.ellipsoid_quantile));
            e->setColor_u8(col.r, col.g, col.b);
            out.insert(e);
        }
        else if (ro.shape == VoxelShape::Cubes)
            cubes->push_back_Voxel(mrpt::opengl::VOXEL_SET_OCCUPIED,
                                   {mrpt::math::TPoint3Df(float(c.x()), float(c.y()), float(c.z())), vs,
                                    mrpt::img::TColor(col.r, col.g, col.b)});
        else
            points->push_back(float(p.x()), float(p.y()), float(p.z()), col.r / 255.f, col.g / 255.f,
                              col.b / 255.f);
    }
    if (points->size()) out.insert(points);
    if (ro.shape == VoxelShape::Cubes && lo.x() <= hi.x())
    {
        // The voxel set is culled against its bounding box: set it.
        const Eigen::Vector3d h = Eigen::Vector3d::Constant(vs);
        cubes->setBoundingBox({lo.x() - h.x(), lo.y() - h.y(), lo.z() - h.z()}, {hi.x() + h.x(), hi.y() + h.y(), hi.z() + h.z()});
        out.insert(cubes);
    }
    if (free_points->size()) out.insert(free_points);
}

}  // namespace pndt
