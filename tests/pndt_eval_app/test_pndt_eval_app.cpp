// pndt-eval on a hand-made map and hand-written GT files: metrics computed by hand, the
// same numbers as evaluating in-process, the export files, and bad input named.
#include <gtest/gtest.h>
#include <pndt/eval/gt_points.h>
#include <pndt/eval/map_eval.h>
#include <pndt/eval/panoptic_codec.h>
#include <pndt/io/sequence.h>
#include <pndt/mrpt/map_files.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../eval/labelled_wall.h"

using namespace pndt;
namespace fs = std::filesystem;

namespace
{
using namespace wall_scene;

struct CliRun
{
    int code = -1;
    std::string out;
};
CliRun run(const std::string& args)
{
    CliRun r;
    FILE* p = ::popen((std::string(PNDT_EVAL_EXE) + " " + args + " 2>&1").c_str(), "r");
    std::array<char, 4096> buf;
    while (p && fgets(buf.data(), int(buf.size()), p)) r.out += buf.data();
    const int status = p ? ::pclose(p) : -1;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

struct Fixture
{
    fs::path dir = fs::temp_directory_path() / ("pndt_eval_app_" + std::to_string(::getpid()));
    std::string map_file = (dir / "map_0000.pndt.gz").string();
    std::vector<Eigen::Vector3d> points;
    std::vector<uint32_t> labels;

    Fixture()
    {
        fs::create_directories(dir);
        auto m = PanopticNDTMap::Create(MapOptions{});
        for (int i = 0; i < 4; ++i) m->core().integrate(labelledWall(), Pose::Identity());
        saveArchive(*m, map_file);
        // Voxel centres on the wall, 162 per half; two floor points far from the map.
        for (int side : {-1, 1})
            for (int i = 0; i < 9; ++i)
                for (int j = 0; j < 18; ++j)
                {
                    points.emplace_back(side * (0.05 + 0.1 * i), -0.85 + 0.1 * j, 2.05);
                    labels.push_back(side < 0 ? eval::encodePanoptic(kWall, 0) : eval::encodePanoptic(kPicture, 7));
                }
        for (double x : {0.05, 0.15})
        {
            points.emplace_back(x, 1.45, 0.5);
            labels.push_back(eval::encodePanoptic(kFloor, 0));
        }
    }
    ~Fixture() { fs::remove_all(dir); }

    std::string writePly(const std::string& name, bool binary, bool with_label = true, size_t cut_bytes = 0) const
    {
        const std::string path = (dir / name).string();
        std::ofstream f(path, std::ios::binary);
        f << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\nelement vertex " << points.size()
          << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n"
          << (with_label ? "property uint label\n" : "") << "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
        std::string body;
        for (size_t i = 0; i < points.size(); ++i)
        {
            const float xyz[3] = {float(points[i].x()), float(points[i].y()), float(points[i].z())};
            if (binary)
            {
                body.append(reinterpret_cast<const char*>(xyz), 12);
                body.push_back(char(200));
                if (with_label) body.append(reinterpret_cast<const char*>(&labels[i]), 4);
            }
            else
                body += std::to_string(xyz[0]) + " " + std::to_string(xyz[1]) + " " + std::to_string(xyz[2]) + " 200" +
                        (with_label ? " " + std::to_string(labels[i]) : "") + "\n";
        }
        body.resize(body.size() - cut_bytes);
        f << body;
        return path;
    }
};

nlohmann::json readJson(const fs::path& p)
{
    std::ifstream f(p);
    nlohmann::json j;
    f >> j;
    return j;
}
}  // namespace

TEST(PndtEvalApp, HandComputedScoresOfATinyCloudFromAsciiAndBinaryPly)
{
    Fixture fx;
    for (bool binary : {false, true})
    {
        SCOPED_TRACE(binary ? "binary" : "ascii");
        const std::string ply = fx.writePly(binary ? "gt_bin.ply" : "gt_ascii.ply", binary);
        const fs::path json = fx.dir / "scores.json";
        const CliRun r = run(fx.map_file + " --gt-ply " + ply + " --classes scannet-20 --json " + json.string());
        ASSERT_EQ(r.code, 0) << r.out;
        const nlohmann::json j = readJson(json).at(0).at("3d");
        // Wall and picture all right (IoU 1), floor missed (2 FN): mIoU 2/3; PQ: wall and
        // picture TP with IoU 1, floor FN: 2/3, things 1, stuff 1/2; AP50 1.
        EXPECT_DOUBLE_EQ(j["miou"].get<double>(), 2.0 / 3);
        EXPECT_DOUBLE_EQ(j["pq"].get<double>(), 2.0 / 3);
        EXPECT_DOUBLE_EQ(j["pq_things"].get<double>(), 1.0);
        EXPECT_DOUBLE_EQ(j["pq_stuff"].get<double>(), 0.5);
        EXPECT_DOUBLE_EQ(j["ap50"].get<double>(), 1.0);
        EXPECT_EQ(j["points"].get<size_t>(), fx.points.size());
        EXPECT_DOUBLE_EQ(j["labelled_share"].get<double>(), 324.0 / 326.0);
        EXPECT_NE(r.out.find("99.4 % labelled"), std::string::npos) << r.out;
    }
}

TEST(PndtEvalApp, EqualsTheInProcessEvaluationAndExportsTheBenchmarkFiles)
{
    Fixture fx;
    // The ScanNet route: a points PLY without labels plus a text file (shift 1000).
    const std::string ply = fx.writePly("mesh.ply", true, false);
    {
        std::ofstream t(fx.dir / "gt.txt");
        for (uint32_t l : fx.labels) t << eval::semanticOf(l) * 1000 + eval::instanceOf(l) << "\n";
    }
    const fs::path json = fx.dir / "s.json", out = fx.dir / "export";
    const CliRun r = run(fx.map_file + " --points " + ply + " --gt-text " + (fx.dir / "gt.txt").string() +
                      " --gt-shift 1000 --json " + json.string() + " --export " + out.string());
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json j = readJson(json).at(0).at("3d");

    const auto map = loadMapArchive(fx.map_file);
    eval::PanopticEvaluator ev(eval::Benchmark::nyuv2_40());
    const eval::PredictedLabels pred = eval::evaluatePoints(map->core(), fx.points, fx.labels, ev);
    const eval::EvalResult direct = ev.result();
    EXPECT_DOUBLE_EQ(j["miou"].get<double>(), direct.semantic.miou);
    EXPECT_DOUBLE_EQ(j["miou_p"].get<double>(), direct.panoptic_semantic.miou);
    EXPECT_DOUBLE_EQ(j["pq"].get<double>(), direct.pq.all.pq);
    EXPECT_DOUBLE_EQ(j["ap50"].get<double>(), direct.ap.ap50);

    // Exported: one line per point, as the ScanNet scripts read them.
    std::ifstream sem(out / "3d" / "semantic" / "map_0000.txt"), pan(out / "3d" / "panoptic" / "map_0000.txt");
    std::string line;
    for (size_t i = 0; i < fx.points.size(); ++i)
    {
        ASSERT_TRUE(std::getline(sem, line));
        EXPECT_EQ(std::stoul(line), pred.semantic[i]);
        ASSERT_TRUE(std::getline(pan, line));
        EXPECT_EQ(std::stoul(line), pred.panoptic[i]);
    }
    EXPECT_FALSE(std::getline(sem, line));
    std::ifstream inst(out / "3d" / "semantic_instance" / "map_0000.txt");
    ASSERT_TRUE(std::getline(inst, line));
    EXPECT_EQ(line.rfind("predicted_masks/map_0000_000.txt 11 ", 0), 0u) << line;  // the picture
}

TEST(PndtEvalApp, BadInputIsNamed)
{
    Fixture fx;
    // No label property.
    const std::string unlabelled = fx.writePly("nolabel.ply", true, false);
    CliRun r = run(fx.map_file + " --gt-ply " + unlabelled);
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find(unlabelled + ": PLY vertices have no 'label' property"), std::string::npos) << r.out;
    // Truncated body.
    const std::string cut = fx.writePly("cut.ply", true, true, 10);
    r = run(fx.map_file + " --gt-ply " + cut);
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find(cut + ": truncated"), std::string::npos) << r.out;
    // A header claiming 10^9 vertices fails before allocating.
    {
        std::ofstream f(fx.dir / "huge.ply");
        f << "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
             "property float z\nproperty uint label\nend_header\n1234";
    }
    r = run(fx.map_file + " --gt-ply " + (fx.dir / "huge.ply").string());
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("1000000000 vertices need"), std::string::npos) << r.out;
    // Text labels that do not match the points.
    {
        std::ofstream t(fx.dir / "short.txt");
        t << "1000\n2000\n";
    }
    r = run(fx.map_file + " --points " + unlabelled + " --gt-text " + (fx.dir / "short.txt").string());
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("short.txt has 2 labels but"), std::string::npos) << r.out;
    // A class outside the benchmark (a wrong --gt-shift, the likeliest mistake): named with its
    // file and line before any map is loaded (it was "PanopticQuality: GT class id 131 at index 0").
    {
        std::ofstream t(fx.dir / "shifted.txt");
        for (size_t i = 0; i < fx.points.size(); ++i) t << (i == 3 ? 131000 : 1000) << "\n";
    }
    r = run(fx.map_file + " --points " + unlabelled + " --gt-text " + (fx.dir / "shifted.txt").string() +
            " --gt-shift 1000");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("shifted.txt: line 4: class 131 is outside the benchmark's classes 0..40 (label 131000 with "
                         "--gt-shift 1000: is the shift right?)"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("voxels,"), std::string::npos) << r.out;
    Fixture bad_class = fx;
    bad_class.labels[5] = eval::encodePanoptic(200, 0);
    const std::string bad_ply = bad_class.writePly("badclass.ply", true);
    r = run(fx.map_file + " --gt-ply " + bad_ply);
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find(bad_ply + ": vertex 5: class 200 is outside the benchmark's classes 0..40"), std::string::npos)
        << r.out;
    // GT of another place: the map labels none of it.
    Fixture far;
    for (auto& p : far.points) p.z() += 50;
    const std::string away = far.writePly("away.ply", true);
    r = run(fx.map_file + " --gt-ply " + away);
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("the map labels only 0.0 % of the 326 GT points"), std::string::npos) << r.out;
    // A map of another class set was scored as NYUv2-40 (its "things" by the benchmark's table).
    {
        const ClassSet nyu = ClassSet::nyuv2_40();
        std::vector<ClassSet::Class> own;
        for (uint32_t i = 0; i < nyu.size(); ++i) own.push_back({nyu.name(i), nyu.isThing(i) && i != 5});
        MapOptions o;
        o.classes = ClassSet(own);
        auto m = PanopticNDTMap::Create(o);
        m->core().integrate(labelledWall(), Pose::Identity());
        const std::string other = (fx.dir / "other_classes.pndt.gz").string();
        saveArchive(*m, other);
        r = run(other + " --gt-ply " + fx.writePly("gt.ply", true));
        EXPECT_EQ(r.code, 1);
        EXPECT_NE(r.out.find(other + ": the map's class set is not the one of the benchmark table 'nyuv2_40' (class 5 "
                                     "is 'chair' (stuff) where the benchmark has 'chair' (thing))"),
                  std::string::npos)
            << r.out;
    }
    // A folder that is not a pndt-map output; a missing map.
    r = run(fx.dir.string() + " --gt-ply " + away);
    EXPECT_NE(r.out.find("no index.json"), std::string::npos) << r.out;
    r = run((fx.dir / "none.pndt.gz").string() + " --gt-ply " + away);
    EXPECT_NE(r.out.find("none.pndt.gz: no such file"), std::string::npos) << r.out;
}

TEST(GtPoints, ShiftedLabelsBecomeTheSixteenBitEncoding)
{
    EXPECT_EQ(eval::panopticFromShifted({5003, 1000, 0}, 1000, "t"),
              (std::vector<uint32_t>{(5u << 16) | 3, 1u << 16, 0}));
    EXPECT_EQ(eval::panopticFromShifted({(5u << 16) | 3}, 65536, "t"), (std::vector<uint32_t>{(5u << 16) | 3}));
    EXPECT_THROW(eval::panopticFromShifted({70000u * 1000}, 1000, "t"), InputError);
}

TEST(PndtEvalApp, GeneratedSceneMappedAndScoredEqualsTheExperimentsEvaluation)
{
    // pndt-generate -> pndt-map -> pndt-eval on the generator's GT cloud, against the
    // in-process evaluatePoints that pndt-experiments uses, on the same map and points.
    const fs::path dir = fs::temp_directory_path() / ("pndt_eval_gen_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const std::string bin = fs::path(PNDT_EVAL_EXE).parent_path().string();
    auto sh = [](const std::string& cmd) { return std::system((cmd + " > /dev/null 2>&1").c_str()); };
    ASSERT_EQ(sh(bin + "/pndt-generate --scene small --frames 6 --formats rawlog,gt --threads 1 --out " +
                 (dir / "scene").string()),
              0);
    ASSERT_EQ(sh(bin + "/pndt-map " + (dir / "scene" / "synth_small_cam_01.rawlog").string() + " --no-progress -o " +
                 (dir / "map").string()),
              0);
    const std::string gt = (dir / "scene/gt/ply/synth_small/cam_01/voxel_0_01_maxdepth_10_0.ply").string();
    const fs::path json = dir / "s.json";
    const CliRun r = run((dir / "map").string() + " --gt-ply " + gt + " --no-tables --json " + json.string());
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json j = readJson(json).at(0).at("3d");

    const auto map = loadMapArchive((dir / "map" / "map_0000.pndt.gz").string());
    const eval::GtPoints points = eval::readPlyPoints(gt, true);
    eval::PanopticEvaluator ev(eval::Benchmark::nyuv2_40());
    eval::evaluatePoints(map->core(), points.points, points.labels, ev);
    const eval::EvalResult direct = ev.result();
    EXPECT_GT(direct.semantic.miou, 0.2);  // a real map of the room
    EXPECT_DOUBLE_EQ(j["miou"].get<double>(), direct.semantic.miou);
    EXPECT_DOUBLE_EQ(j["miou_p"].get<double>(), direct.panoptic_semantic.miou);
    EXPECT_DOUBLE_EQ(j["pq"].get<double>(), direct.pq.all.pq);
    fs::remove_all(dir);
}

TEST(PndtEvalApp, TwoDimensionalScoresOnANicrSequenceEqualTheInProcessRenderedEvaluation)
{
    // pndt-generate writes the nicr layout (GT PNGs, poses, intrinsics) and the rawlog;
    // pndt-eval --nicr renders the map into every 2nd frame; the same frames scored in
    // process with evaluateView give the same numbers, and the RGB8 PNGs are written.
    const fs::path dir = fs::temp_directory_path() / ("pndt_eval_2d_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const std::string bin = fs::path(PNDT_EVAL_EXE).parent_path().string();
    auto sh = [](const std::string& cmd) { return std::system((cmd + " > /dev/null 2>&1").c_str()); };
    ASSERT_EQ(sh(bin + "/pndt-generate --scene small --frames 6 --formats rawlog,nicr --threads 1 --out " +
                 (dir / "scene").string()),
              0);
    ASSERT_EQ(sh(bin + "/pndt-map " + (dir / "scene" / "synth_small_cam_01.rawlog").string() + " --no-progress -o " +
                 (dir / "map").string()),
              0);
    const std::string split = (dir / "scene" / "nicr" / "test").string(), seq = "synth_small/cam_01";
    const fs::path json = dir / "s.json", out = dir / "export";
    const CliRun r = run((dir / "map" / "map_0000.pndt.gz").string() + " --nicr " + split + " --sequence " + seq +
                         " --every 2 --no-tables --json " + json.string() + " --export " + out.string());
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json j = readJson(json).at(0).at("2d");
    EXPECT_EQ(j["frames"].get<size_t>(), 3u);

    const auto map = loadMapArchive((dir / "map" / "map_0000.pndt.gz").string());
    const io::RgbdSequence s = io::openNicrSequence(split, seq);
    ASSERT_EQ(s.size(), 6u);
    eval::PanopticEvaluator ev(eval::Benchmark::nyuv2_40());
    size_t pngs = 0;
    for (size_t i = 0; i < s.size(); i += 2)
    {
        const io::RgbdFrame f = s.load(i);
        Image<uint32_t> gt_instance;
        gt_instance.resize(f.instance_gt.width, f.instance_gt.height, 0u);
        for (size_t k = 0; k < gt_instance.data.size(); ++k) gt_instance.data[k] = f.instance_gt.data[k];
        eval::evaluateView(map->core(), *f.T_world_cam, f.K, f.semantic_gt, gt_instance, ev);
        pngs += fs::exists(out / "2d" / "panoptic_2d" / (f.id + ".png"));
    }
    const eval::EvalResult direct = ev.result();
    EXPECT_GT(direct.semantic.miou, 0.2);
    EXPECT_DOUBLE_EQ(j["miou"].get<double>(), direct.semantic.miou);
    EXPECT_DOUBLE_EQ(j["pq"].get<double>(), direct.pq.all.pq);
    EXPECT_EQ(pngs, 3u);
    fs::remove_all(dir);
}
