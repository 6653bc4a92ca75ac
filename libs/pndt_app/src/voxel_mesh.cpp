#include "voxel_mesh.h"

#include <pndt/mrpt/voxel_colors.h>

namespace pndt::app
{
namespace
{
// The six faces: neighbour offset, and the face's 4 corners (unit cube, counter-clockwise seen from outside).
struct Face
{
    int dx, dy, dz;
    float shade;  // light from above and one side: faces read apart
    float corners[4][3];
};
constexpr Face kFaces[6] = {
    {1, 0, 0, 0.80f, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}},
    {-1, 0, 0, 0.65f, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}},
    {0, 1, 0, 0.70f, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}},
    {0, -1, 0, 0.90f, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}},
    {0, 0, 1, 1.00f, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}},
    {0, 0, -1, 0.50f, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}},
};

template <typename Visit>
void forEachExposedFace(const PanopticMap& map, Visit&& visit)
{
    const auto& store = map.voxels();
    // The ceiling would hide the room from above: left out, as in the floor plan.
    const int ceiling = map.options().classes.find("ceiling");
    for (uint32_t i = 0; i < store.size(); ++i)
    {
        if (!map.isOccupied(store[i])) continue;
        if (ceiling > 0 && map.panopticLabel(i).semantic == ceiling) continue;
        const VoxelKey k = store.key(i);
        for (const Face& f : kFaces)
        {
            const uint32_t n = store.find(VoxelKey{k.x + f.dx, k.y + f.dy, k.z + f.dz});
            if (n != kNoRecord && map.isOccupied(store[n])) continue;
            visit(i, k, f);
        }
    }
}
}  // namespace

size_t exposedFaceCount(const PanopticMap& map)
{
    size_t n = 0;
    forEachExposedFace(map, [&](uint32_t, const VoxelKey&, const Face&) { ++n; });
    return n;
}

mrpt::opengl::CSetOfTriangles::Ptr exposedFaceMesh(const PanopticMap& map)
{
    map.finalize();
    auto mesh = mrpt::opengl::CSetOfTriangles::Create();
    const double s = map.options().voxel_size;
    forEachExposedFace(map, [&](uint32_t i, const VoxelKey& k, const Face& f) {
        const Eigen::Vector3d lo = map.grid().minCorner(k);
        const Rgb c = voxelColor(map, i, ColorMode::Panoptic);
        const mrpt::img::TColor colour(uint8_t(c.r * f.shade), uint8_t(c.g * f.shade), uint8_t(c.b * f.shade));
        mrpt::math::TPoint3Df p[4];
        for (int v = 0; v < 4; ++v)
            p[v] = mrpt::math::TPoint3Df(float(lo.x() + s * f.corners[v][0]), float(lo.y() + s * f.corners[v][1]),
                                         float(lo.z() + s * f.corners[v][2]));
        for (const auto& tri : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}})
        {
            mrpt::opengl::TTriangle t(p[tri[0]], p[tri[1]], p[tri[2]]);
            for (auto& vert : t.vertices) vert.setColor(colour);
            mesh->insertTriangle(t);
        }
    });
    return mesh;
}
}  // namespace pndt::app
