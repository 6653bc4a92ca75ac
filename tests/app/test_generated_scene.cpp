// pndt-map end to end on a generated scene with network-like noisy segmentation
// (issue 4): N maps for N periods that load back as written, and a report that
// lists the furniture with its class near the truth.
//
// Measured (doc/design-decisions.md "Instances keep one class"): all 6 large
// pieces of furniture within one voxel (0.10 m; 0.02-0.07 m). With the paper's
// rules alone it was 0 of 6 (merged chair + rug, TV + cabinet); without the
// finalisation (fragment absorption, label fill) 4 of 6: a table and a cabinet
// whose parts the network only ever labelled as another class with low
// confidence stayed unlabelled or a separate fragment (0.14 and 0.22 m).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <pndt/data/dataset.h>
#include <pndt/mrpt/map_files.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <tuple>

#include "cli_fixture.h"

using namespace cli;

namespace
{
nlohmann::json readJson(const fs::path& p)
{
    std::ifstream f(p);
    return nlohmann::json::parse(f);
}
}  // namespace

TEST(GeneratedScene, NoisySegmentationShortTermMapsAndFurnitureReport)
{
    const fs::path dir = tempDir("generated");
    pndt::data::GeneratorOptions g;  // scene "small", 60 frames 640x480, 0.2 s apart, noise on
    pndt::data::OutputOptions o;
    o.out_dir = (dir / "scene").string();
    o.nicr = o.gt = false;
    const auto report = pndt::data::generateDataset(g, o);
    ASSERT_FALSE(report.rawlog_path.empty());

    // 60 frames over 12 s in 4 s periods: 3 maps.
    const RunResult r = run(mapExe() + report.rawlog_path + " -o " + (dir / "maps").string() + " --period 4");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto index = readJson(dir / "maps" / "index.json");
    ASSERT_EQ(index.size(), 3u) << index.dump(1);
    for (const auto& e : index)
    {
        const auto m = pndt::loadMapArchive((dir / "maps" / e["file"].get<std::string>()).string());
        EXPECT_EQ(m->core().voxels().size(), e["voxels"].get<size_t>());
        EXPECT_EQ(m->core().instances().size(), e["instances"].get<size_t>());
    }

    // One map of the whole walk for the report.
    const RunResult full = run(mapExe() + report.rawlog_path + " -o " + (dir / "full").string());
    ASSERT_EQ(full.code, 0) << full.out;
    const auto inst = readJson(dir / "full" / "instances.json");

    // Truth: the seen surface of each object, 1 cm voxels of all GT pixels.
    const pndt::data::SequenceGenerator gen(g);
    std::map<uint32_t, std::set<std::tuple<int, int, int>>> cells;
    std::map<uint32_t, uint16_t> cls;
    for (size_t i = 0; i < gen.size(); ++i)
    {
        const auto f = gen.frame(i);
        for (int row = 0; row < f.K.height; ++row)
            for (int col = 0; col < f.K.width; ++col)
            {
                const uint32_t z = f.gt_instance.at(row, col);
                const float d = f.depth_clean.at(row, col);
                if (z == 0 || !(d > 0)) continue;
                const Eigen::Vector3d p = f.T_world_cam * f.K.unproject(col, row, d);
                cells[z].emplace(int(std::floor(p.x() * 100)), int(std::floor(p.y() * 100)),
                                 int(std::floor(p.z() * 100)));
                cls[z] = f.gt_semantic.at(row, col);
            }
    }
    // Furniture: the large objects (>= 0.3 m² of seen surface).
    const std::set<uint16_t> furniture = {3, 4, 5, 6, 7, 10, 12, 14, 15, 17, 24, 32, 39};
    int checked = 0, found = 0;
    for (const auto& [z, set] : cells)
    {
        if (!furniture.count(cls[z]) || set.size() < 3000) continue;
        Eigen::Vector3d truth = Eigen::Vector3d::Zero();
        for (const auto& [x, y, w] : set) truth += Eigen::Vector3d(x + 0.5, y + 0.5, w + 0.5) / 100.0;
        truth /= double(set.size());
        const std::string name = pndt::ClassSet::nyuv2_40().name(cls[z]);
        double best = 1e9;
        if (inst["classes"].contains(name))
            for (const auto& mi : inst["classes"][name])
                best = std::min(best, (Eigen::Vector3d(mi["centroid"][0], mi["centroid"][1], mi["centroid"][2]) -
                                       truth).norm());
        std::printf("[measured] %s (GT %u, %zu cm² seen): nearest map %s at %.3f m\n", name.c_str(), z, set.size(),
                    name.c_str(), best);
        ++checked;
        found += best < 0.10;
        // Every piece of furniture is in the report with its class, within one voxel.
        EXPECT_LT(best, 0.10) << name << " " << z << " truth " << truth.transpose() << "\n" << inst.dump(1);
    }
    EXPECT_GE(checked, 5) << "the default scene has six large pieces of furniture";
    std::printf("[measured] furniture within one voxel (0.10 m): %d of %d\n", found, checked);
    EXPECT_EQ(found, checked);
}
