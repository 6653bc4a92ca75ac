// The map pictures on hand-made maps: faces of the voxel mesh counted by hand, floor-plan
// cells coloured by the class of their highest non-ceiling voxel, legends.
#include <gtest/gtest.h>
#include <pndt/app/map_pictures.h>

#include "voxel_mesh.h"

using namespace pndt;

namespace
{
/// A map whose occupied voxels are `cells` (key, class), each with a label record.
PanopticMap handMadeMap(const std::vector<std::pair<VoxelKey, uint16_t>>& cells)
{
    PanopticMap map(MapOptions{});
    std::vector<uint64_t> keys;
    std::vector<Voxel> voxels;
    std::vector<SurfaceRecord> surfaces(cells.size());
    std::vector<LabelRecord> labels(cells.size());
    for (size_t i = 0; i < cells.size(); ++i)
    {
        keys.push_back(cells[i].first.packed());
        voxels.push_back({1.f, uint32_t(i)});
        surfaces[i].labels = uint32_t(i);
        labels[i].semantic.add(uint8_t(cells[i].second), 1.f);
        labels[i].n_l = 1;
    }
    map.restore(keys, voxels, surfaces, labels, {}, 1);
    return map;
}

cv::Vec3b bgrOf(Rgb c) { return {c.b, c.g, c.r}; }
}  // namespace

TEST(MapPictures, TheVoxelMeshDrawsOnlyExposedFaces)
{
    constexpr uint16_t kWall = 1, kCeiling = 22;
    EXPECT_EQ(app::exposedFaceCount(handMadeMap({{{0, 0, 0}, kWall}})), 6u);
    // Two touching voxels hide the face between them on both: 12 - 2.
    EXPECT_EQ(app::exposedFaceCount(handMadeMap({{{0, 0, 0}, kWall}, {{1, 0, 0}, kWall}})), 10u);
    // A 2x2x1 slab: 24 - 8 inner faces.
    EXPECT_EQ(app::exposedFaceCount(handMadeMap(
                  {{{0, 0, 0}, kWall}, {{1, 0, 0}, kWall}, {{0, 1, 0}, kWall}, {{1, 1, 0}, kWall}})),
              16u);
    // Ceiling voxels are left out (the room stays visible from above).
    EXPECT_EQ(app::exposedFaceCount(handMadeMap({{{0, 0, 0}, kWall}, {{5, 5, 5}, kCeiling}})), 6u);
    EXPECT_EQ(app::exposedFaceMesh(handMadeMap({{{0, 0, 0}, kWall}, {{1, 0, 0}, kWall}}))->getTrianglesCount(), 20u);
}

TEST(MapPictures, FloorPlanCellsTakeTheClassOfTheirHighestVoxelBelowTheCeiling)
{
    constexpr uint16_t kWall = 1, kFloor = 2, kTable = 7, kCeiling = 22;
    // Cell (0,0): floor under a table (table shows); cell (1,0): floor under the ceiling
    // (floor shows); cell (2,0): wall.
    const PanopticMap map = handMadeMap({{{0, 0, 0}, kFloor},
                                         {{0, 0, 7}, kTable},
                                         {{1, 0, 0}, kFloor},
                                         {{1, 0, 25}, kCeiling},
                                         {{2, 0, 3}, kWall}});
    const int s = 8, margin = 40;  // floorPlan's scale and margin
    const cv::Mat img = app::floorPlan(map, s);
    ASSERT_EQ(img.type(), CV_8UC3);
    const auto cellCentre = [&](int x) { return img.at<cv::Vec3b>(margin + s / 2, margin + x * s + s / 2); };
    EXPECT_EQ(cellCentre(0), bgrOf(classColor(kTable)));
    EXPECT_EQ(cellCentre(1), bgrOf(classColor(kFloor)));
    EXPECT_EQ(cellCentre(2), bgrOf(classColor(kWall)));
    // Width: 3 cells + margins + the legend panel (190 px).
    EXPECT_EQ(img.cols, 3 * s + 2 * margin + 190);
}

TEST(MapPictures, LegendListsClassesByPixelsWithTheirColours)
{
    const ClassSet classes = ClassSet::nyuv2_40();
    std::vector<uint64_t> pixels(classes.size(), 0);
    pixels[5] = 10;   // chair
    pixels[1] = 100;  // wall
    pixels[0] = 1000; // void: never listed
    const auto entries = app::classLegend(pixels, classes);
    ASSERT_EQ(entries.size(), 2u);
    EXPECT_EQ(entries[0].text, "wall");
    EXPECT_EQ(entries[1].text, "chair");
    const cv::Mat image(30, 40, CV_8UC3, cv::Scalar(0, 0, 0));
    const cv::Mat out = app::withLegend(image, entries);
    EXPECT_EQ(out.cols, 40 + 190);
    EXPECT_EQ(out.rows, 12 + 22 * 2);  // taller than the image: room for both lines
    EXPECT_EQ(out.at<cv::Vec3b>(8 + 8, 40 + 18), bgrOf(classColor(1)));  // the first swatch's centre
}
