// RawlogFrameWriter: what it writes reads back as the same frame and pose.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/mrpt/observation_frame.h>
#include <pndt/mrpt/rawlog_frames.h>

#include <filesystem>

#include "observation_fixtures.h"

using namespace pndt;
namespace fs = std::filesystem;

namespace
{
PanopticFrame smallFrame(int seed)
{
    PanopticFrame f;
    f.K = {8, 6, 5.0, 5.0, 3.5, 2.5};
    f.depth.resize(8, 6);
    f.semantic.resize(8, 6);
    f.semantic_score.resize(8, 6);
    f.instance.resize(8, 6);
    f.panoptic_score.resize(8, 6);
    for (size_t i = 0; i < f.depth.data.size(); ++i)
    {
        f.depth.data[i] = 1.0f + 0.001f * float(i + seed);  // whole millimetres
        f.semantic.data[i] = uint16_t((i + seed) % 41);
        f.semantic_score.data[i] = 0.5f;
        f.instance.data[i] = i % 3 ? uint32_t(100 + seed) : 0;
        f.panoptic_score.data[i] = 0.25f;
    }
    return f;
}
}  // namespace

TEST(RawlogFrames, WrittenFramesReadBackIdentical)
{
    const fs::path path = fs::temp_directory_path() / ("pndt_frames_" + std::to_string(::getpid()) + ".rawlog");
    Pose T = Pose::Identity();
    T.translation() << 1, 2, 3;
    T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    {
        RawlogFrameWriter w(path.string());
        w.setSensorPose(mrpt::poses::CPose3D(0, 0, 1.2, 0, 0, 0));
        for (int i = 0; i < 3; ++i) w.write(smallFrame(i), 100.0 + i, T);
        EXPECT_FALSE(fs::exists(path));  // not before commit
        w.commit();
    }
    ASSERT_TRUE(fs::exists(path));
    mrpt::io::CFileGZInputStream in(path.string());
    auto a = mrpt::serialization::archiveFrom(in);
    for (int i = 0; i < 3; ++i)
    {
        mrpt::serialization::CSerializable::Ptr o1, o2, o3, o4;
        a >> o1 >> o2 >> o3 >> o4;
        auto pose = std::dynamic_pointer_cast<mrpt::obs::CObservationRobotPose>(o1);
        auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o2);
        auto sem = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(o3);
        auto inst = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(o4);
        ASSERT_TRUE(pose && scan && sem && inst);
        EXPECT_EQ(sem->sensorLabel, "RGBD_PANOPTIC_SEMANTIC");
        EXPECT_EQ(inst->sensorLabel, "RGBD_PANOPTIC_INSTANCE");
        EXPECT_EQ(sem->timestamp, scan->timestamp);
        const Pose back = cameraPoseInWorld(pose->pose.mean, scan->sensorPose);
        EXPECT_TRUE(back.isApprox(T, 1e-9));
        PanopticFrame f;
        depthFrameFrom(*scan, f);
        attachPanopticLabels(*sem, *inst, f);
        const PanopticFrame ref = smallFrame(i);
        for (size_t p = 0; p < ref.depth.data.size(); ++p)
        {
            EXPECT_NEAR(f.depth.data[p], ref.depth.data[p], 1e-6);
            EXPECT_EQ(f.semantic.data[p], ref.semantic.data[p]);
            EXPECT_EQ(f.instance.data[p], ref.instance.data[p]);
            EXPECT_NEAR(f.semantic_score.data[p], 0.5f, 1e-4);
            EXPECT_NEAR(f.panoptic_score.data[p], 0.25f, 1e-4);
        }
    }
    fs::remove(path);
}

TEST(RawlogFrames, UncommittedWriterLeavesNothing)
{
    const fs::path dir = fs::temp_directory_path() / ("pndt_frames_dir_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    {
        RawlogFrameWriter w((dir / "x.rawlog").string());
        w.write(smallFrame(0), 1.0, std::nullopt);
    }
    EXPECT_TRUE(fs::is_empty(dir));
    fs::remove_all(dir);
}

// Issue #23, found by fuzz_rawlog: an id+score value beyond 32 bits (7.18e22) was converted
// to uint32_t (undefined behaviour, UBSan: "outside the range of representable values").
TEST(RawlogFrames, IdScoreValuesBeyond32BitsAreRejectedNamingThePixel)
{
    for (const float v : {7.18343e22f, 4294967296.f})
    {
        const auto scan = fixtures::wallScan(0);
        PanopticFrame f;
        depthFrameFrom(*scan, f);
        const auto sem = fixtures::semanticImage(0);
        const auto inst = fixtures::labelImage(0, "_PANOPTIC_INSTANCE", 1.5f, v);
        try
        {
            attachPanopticLabels(*sem, *inst, f);
            ADD_FAILURE() << "no error for " << v;
        }
        catch (const InputError& e)
        {
            EXPECT_NE(std::string(e.what()).find("invalid id+score value"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("row 0, col 0"), std::string::npos) << e.what();
        }
    }
}
