// pndt::CObservationPanopticMap: a short-term map as an MRPT observation. Round
// trip through an archive, its description, and MRPT's stock rawlog-edit on a
// rawlog of them (list the maps' stamps, cut by time) with the plugin (-p).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>
#include <pndt/mrpt/CObservationPanopticMap.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "observation_fixtures.h"

namespace fs = std::filesystem;
using pndt::CObservationPanopticMap;

namespace
{
std::string run(const std::string& cmd)
{
    std::string out;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    if (!p) return out;
    std::array<char, 4096> buf;
    while (fgets(buf.data(), int(buf.size()), p)) out += buf.data();
    ::pclose(p);
    return out;
}

fs::path tempDir(const char* name)
{
    const fs::path d = fs::temp_directory_path() / (std::string("pndt_mapobs_") + name + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

/// A map of `frames` labelled wall frames (left half chair instance, right half wall).
pndt::PanopticNDTMap::Ptr labelledMap(int frames)
{
    using namespace fixtures;
    auto m = pndt::PanopticNDTMap::Create();
    const mrpt::poses::CPose3D robot;
    for (int i = 0; i < frames; ++i)
    {
        m->insertObservation(*wallScan(i, 2.0f - 0.05f * float(i)), robot);
        m->insertObservation(*semanticImage(i), robot);
        m->insertObservation(*instanceImage(i), robot);
    }
    m->flushPending();
    m->core().finalize();
    return m;
}

CObservationPanopticMap::Ptr wrap(const pndt::PanopticNDTMap::Ptr& m, double t_end, uint32_t sequence)
{
    auto o = CObservationPanopticMap::Create();
    o->timestamp = fixtures::stamp(t_end);
    o->start = fixtures::stamp(t_end - 1);
    o->frames = 3;
    o->sequence = sequence;
    o->map = m;
    return o;
}

constexpr double kBase = 1.7e9;  // fixtures::stamp(t) = kBase + t
}  // namespace

TEST(MapObservation, RoundTripThroughAnArchiveKeepsTheMap)
{
    const auto m = labelledMap(3);
    ASSERT_GT(m->core().voxels().size(), 0u);
    ASSERT_GT(m->core().instances().size(), 0u);
    auto o = wrap(m, 12.5, 7);
    o->sensorLabel = "MY_MAPS";
    mrpt::io::CMemoryStream buf;
    auto out = mrpt::serialization::archiveFrom(buf);
    out << *o;  // as an object: class name + version, like a rawlog entry
    buf.Seek(0);
    auto in = mrpt::serialization::archiveFrom(buf);
    mrpt::serialization::CSerializable::Ptr read;
    in >> read;
    const auto back = std::dynamic_pointer_cast<CObservationPanopticMap>(read);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->sensorLabel, "MY_MAPS");
    EXPECT_EQ(back->timestamp, o->timestamp);
    EXPECT_EQ(back->start, o->start);
    EXPECT_EQ(back->frames, 3u);
    EXPECT_EQ(back->sequence, 7u);
    mrpt::poses::CPose3D p(1, 2, 3, 0, 0, 0);
    back->getSensorPose(p);
    EXPECT_EQ(p, mrpt::poses::CPose3D());  // the world
    ASSERT_TRUE(back->map);
    const pndt::PanopticMap& a = m->core();
    const pndt::PanopticMap& b = back->map->core();
    ASSERT_EQ(b.voxels().size(), a.voxels().size());
    EXPECT_EQ(b.instances().size(), a.instances().size());
    EXPECT_EQ(b.occupiedCount(), a.occupiedCount());
    EXPECT_EQ(b.voxels().packedKeys(), a.voxels().packedKeys());
    for (uint32_t i : {0u, uint32_t(a.voxels().size() / 2), uint32_t(a.voxels().size() - 1)})
    {
        EXPECT_EQ(b.voxels()[i].occ, a.voxels()[i].occ) << i;
        EXPECT_EQ(b.panopticLabel(i), a.panopticLabel(i)) << i;
        EXPECT_EQ(b.pointOf(i), a.pointOf(i)) << i;
    }
}

TEST(MapObservation, DescriptionListsVoxelsAndInstancesPerClass)
{
    const auto m = labelledMap(3);
    std::ostringstream text;
    wrap(m, 12.5, 2)->getDescriptionAsText(text);
    const std::string s = text.str();
    EXPECT_NE(s.find("Short-term panoptic map #2: 3 frames"), std::string::npos) << s;
    EXPECT_NE(s.find("PANOPTIC_MAP"), std::string::npos) << s;
    // One row per class present: the chair (5) with its instances, the wall (1).
    const auto& classes = m->core().options().classes;
    uint64_t chair_voxels = 0;
    for (uint32_t i = 0; i < m->core().voxels().size(); ++i)
        chair_voxels += m->core().isOccupied(m->core().voxels()[i]) && m->core().panopticLabel(i).semantic == 5;
    ASSERT_GT(chair_voxels, 0u);
    int chairs = 0;
    for (const auto& inst : m->core().instances()) chairs += inst.semantic == 5;
    ASSERT_GT(chairs, 0);
    char row[128];
    std::snprintf(row, sizeof row, "%-24s %10llu %10d", ("5 " + classes.name(5)).c_str(),
                  (unsigned long long)chair_voxels, chairs);
    EXPECT_NE(s.find(row), std::string::npos) << "missing row '" << row << "' in\n" << s;
    EXPECT_NE(s.find("1 " + classes.name(1)), std::string::npos) << s;
}

TEST(MapObservation, StockRawlogEditListsAndCutsMapsByTime)
{
    const fs::path dir = tempDir("cut");
    const std::string path = (dir / "maps.rawlog").string();
    std::vector<size_t> voxels;
    {
        mrpt::io::CFileGZOutputStream f(path);
        auto a = mrpt::serialization::archiveFrom(f);
        for (int k = 0; k < 4; ++k)  // maps handed over at 10, 20, 30, 40 s
        {
            const auto m = labelledMap(1 + k);
            voxels.push_back(m->core().voxels().size());
            a << *wrap(m, 10.0 * (k + 1), uint32_t(k));
        }
    }
    const std::string plugin = std::string(" -p ") + PNDT_PLUGIN_PATH;
    const std::string info = run("rawlog-edit" + plugin + " --info -i " + path);
    EXPECT_NE(info.find("Overall number of objects         : 4"), std::string::npos) << info;
    EXPECT_NE(info.find("All sensor labels                 : PANOPTIC_MAP"), std::string::npos) << info;

    const auto listTimestamps = [&](const std::string& rawlog) {
        const std::string txt = (dir / "ts.txt").string();
        fs::remove(txt);
        const std::string out = run("rawlog-edit" + plugin + " --list-timestamps -i " + rawlog +
                                    " --text-file-output " + txt);
        std::vector<double> stamps;
        std::ifstream f(txt);
        double t;
        std::string label, cls;
        while (f >> t >> label >> cls)
        {
            EXPECT_EQ(label, "PANOPTIC_MAP");
            EXPECT_EQ(cls, "pndt::CObservationPanopticMap");
            stamps.push_back(t - kBase);
        }
        EXPECT_FALSE(stamps.empty()) << out;
        return stamps;
    };
    const auto all = listTimestamps(path);
    ASSERT_EQ(all.size(), 4u);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(all[size_t(k)], 10.0 * (k + 1), 1e-3);

    // --cut keeps exactly the maps handed over inside [15, 35] s.
    const std::string cut = (dir / "cut.rawlog").string();
    const std::string cut_out = run(fmt::format("rawlog-edit{} --cut --from-time {:.3f} --to-time {:.3f} -i {} -o {}",
                                                plugin, kBase + 15, kBase + 35, path, cut));
    const auto kept = listTimestamps(cut);
    ASSERT_EQ(kept.size(), 2u) << cut_out;
    EXPECT_NEAR(kept[0], 20.0, 1e-3);
    EXPECT_NEAR(kept[1], 30.0, 1e-3);
    // ... and they are whole maps.
    mrpt::io::CFileGZInputStream f(cut);
    auto a = mrpt::serialization::archiveFrom(f);
    for (size_t k : {1u, 2u})
    {
        mrpt::serialization::CSerializable::Ptr o;
        a >> o;
        const auto m = std::dynamic_pointer_cast<CObservationPanopticMap>(o);
        ASSERT_TRUE(m && m->map);
        EXPECT_EQ(m->sequence, k);
        EXPECT_EQ(m->map->core().voxels().size(), voxels[k]);
    }

    // Without the plugin the stock tool names the class it does not know.
    const std::string without = run("rawlog-edit --info -i " + path);
    EXPECT_NE(without.find("pndt::CObservationPanopticMap"), std::string::npos) << without;
    fs::remove_all(dir);
}

// RawLogViewer is a GUI: run it on a virtual X server (xvfb-run) and list its
// windows with xwininfo after a few seconds. A file it cannot load opens a
// "Zero entries loaded" (or "Error loading file") box; the negative control,
// without the plugin, shows that the probe sees it.
TEST(MapObservation, StockRawLogViewerOpensAMapsRawlogHeadless)
{
    for (const char* tool : {"xvfb-run", "RawLogViewer", "xwininfo"})
        if (run(std::string("command -v ") + tool).empty()) GTEST_SKIP() << tool << " not installed";
    const fs::path dir = tempDir("viewer");
    const std::string path = (dir / "maps.rawlog").string();
    {
        mrpt::io::CFileGZOutputStream f(path);
        auto a = mrpt::serialization::archiveFrom(f);
        for (int k = 0; k < 2; ++k) a << *wrap(labelledMap(2 + k), 10.0 * (k + 1), uint32_t(k));
    }
    const auto windows = [&](const std::string& args) {
        const std::string log = (dir / "viewer.log").string();
        const std::string script = fmt::format(
            "RawLogViewer {} {} >{} 2>&1 & p=$!; "
            // until it has settled (its tip window, or an error box; at most 20 s), then 2 s more
            "for i in $(seq 40); do sleep 0.5; xwininfo -root -tree | grep -q -e \"Tip of the Day\" "
            "-e \"Zero entries\" -e \"Error loading\" && break; done; sleep 2; "
            "kill -0 $p && echo VIEWER_ALIVE; xwininfo -root -tree; kill $p; wait $p; echo; cat {}",
            args, path, log, log);
        return run("timeout 40 xvfb-run -a sh -c '" + script + "'");
    };
    const std::string with = windows(std::string("-l ") + PNDT_PLUGIN_PATH);
    EXPECT_NE(with.find("VIEWER_ALIVE"), std::string::npos) << with;
    EXPECT_NE(with.find("\"RawlogViewer - Part of the MRPT project\""), std::string::npos) << with;
    EXPECT_EQ(with.find("Zero entries loaded"), std::string::npos) << with;
    EXPECT_EQ(with.find("Error"), std::string::npos) << with;
    EXPECT_EQ(with.find("not registered"), std::string::npos) << with;

    const std::string without = windows("");
    EXPECT_NE(without.find("Zero entries loaded"), std::string::npos) << without;
    fs::remove_all(dir);
}
