// Writers: .npz, PNG encodings, nicr JSON, PLY / benchmark text, atomic files, GT cloud;
// everything read back with pndt_io's readers where one exists.
#include <gtest/gtest.h>
#include <pndt/data/atomic_file.h>
#include <pndt/data/gt_cloud.h>
#include <pndt/data/gt_writers.h>
#include <pndt/data/nicr_writer.h>
#include <pndt/data/npz_writer.h>
#include <pndt/io/images.h>
#include <pndt/io/intrinsics.h>
#include <pndt/io/npz.h>
#include <pndt/io/poses.h>

#include <cerrno>
#include <cstring>
#include <sstream>

#include "data_test_util.h"
#include "file_size_limit.h"

using namespace pndt;
using namespace pndt::data;
namespace fs = std::filesystem;

TEST(NpzWriter, RoundTripsThroughPndtIo)
{
    const test::TempDir dir("npz");
    Image<uint32_t> ids(7, 5, 0);
    Image<float> scores(7, 5, 0.f);
    for (size_t i = 0; i < ids.size(); ++i)
    {
        ids.data[i] = static_cast<uint32_t>(i * 37 % 41);
        scores.data[i] = static_cast<float>((i % 11) / 10.0);  // includes 1.0 -> clamped to 0.999
    }
    const std::vector<float> packed = packIdScore(ids, scores);
    for (bool compress : {true, false})
    {
        const std::string p = dir / (compress ? "d.npz" : "s.npz");
        writeNpzFloat32(p, {1, 5, 7}, packed, compress);
        EXPECT_EQ(io::listNpzArrays(p), std::vector<std::string>{"arr_0"});
        const io::NpyArray a = io::readNpzArray(p);
        EXPECT_EQ(a.shape, (std::vector<size_t>{1, 5, 7}));
        EXPECT_EQ(a.data, packed);
        const Image<float> img = io::readNpzImage(p);
        const io::IdScoreImages dec = io::decodeIdScore(img, p);
        for (size_t i = 0; i < ids.size(); ++i)
        {
            EXPECT_EQ(dec.ids.data[i], ids.data[i]);
            EXPECT_NEAR(dec.scores.data[i], std::min(scores.data[i], 0.999f), 1e-5);
        }
    }
    // (H, W) shape for the instance file.
    writeNpzFloat32(dir / "hw.npz", {5, 7}, packed);
    EXPECT_EQ(io::readNpzArray(dir / "hw.npz").shape, (std::vector<size_t>{5, 7}));
    EXPECT_THROW(writeNpzFloat32(dir / "bad.npz", {2, 2}, packed), std::runtime_error);
}

TEST(NpzWriter, HeaderIsAlignedNumpyV1)
{
    const std::string b = npyFloat32Bytes({3}, {1.f, 2.f, 3.f});
    EXPECT_EQ(b.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    const size_t header_len = static_cast<uint8_t>(b[8]) | (static_cast<uint8_t>(b[9]) << 8);
    EXPECT_EQ((10 + header_len) % 64, 0u);
    EXPECT_NE(b.find("'shape': (3,)"), std::string::npos);
    EXPECT_EQ(b.size(), 10 + header_len + 12);
}

TEST(PngWriter, DepthLabelsAndInstancesReadBack)
{
    const test::TempDir dir("png");
    Image<uint16_t> depth(9, 4, 0), sem(9, 4, 0);
    Image<uint32_t> ins(9, 4, 0);
    for (size_t i = 0; i < depth.size(); ++i)
    {
        depth.data[i] = static_cast<uint16_t>(i * 1234 % 65536);
        sem.data[i] = static_cast<uint16_t>(i % 41);
        ins.data[i] = static_cast<uint32_t>(i * 997 % 65536);
    }
    writeFileAtomic(dir / "d.png", encodePng16(depth));
    writeFileAtomic(dir / "s.png", encodePng8(sem));
    writeFileAtomic(dir / "i.png", encodeInstancePng(sem, ins));
    const Image<float> d = io::readDepthImage(dir / "d.png");
    for (size_t i = 0; i < depth.size(); ++i) EXPECT_EQ(std::lround(d.data[i] * 1000.0), depth.data[i]);
    EXPECT_EQ(io::readLabelImage(dir / "s.png").data, sem.data);
    const Image<uint16_t> back = io::readLabelImage(dir / "i.png");
    for (size_t i = 0; i < ins.size(); ++i) EXPECT_EQ(back.data[i], ins.data[i]);
    sem.data[0] = 300;
    EXPECT_THROW(encodePng8(sem), InputError);
}

TEST(NicrJson, IntrinsicsAndExtrinsicsReadBack)
{
    const test::TempDir dir("json");
    const CameraIntrinsics K{640, 480, 577.87, 577.87, 319.5, 239.5};
    writeFileAtomic(dir / "k.json", nicrIntrinsicsJson(K, true));
    const io::NicrIntrinsics n = io::readNicrIntrinsicsJson(dir / "k.json");
    ASSERT_TRUE(n.a.has_value());
    EXPECT_DOUBLE_EQ(*n.a, 0.001);
    const CameraIntrinsics back = n.toPixels(640, 480);
    EXPECT_NEAR(back.fx, K.fx, 1e-9);
    EXPECT_NEAR(back.fy, K.fy, 1e-9);
    EXPECT_NEAR(back.cx, K.cx, 1e-9);
    EXPECT_NEAR(back.cy, K.cy, 1e-9);
    Pose T = Pose::Identity();
    T.linear() = Eigen::AngleAxisd(2.5, Eigen::Vector3d(0.2, -1, 0.4).normalized()).toRotationMatrix();
    T.translation() << 1.5, -2.25, 1.45;
    writeFileAtomic(dir / "e.json", nicrExtrinsicsJson(T));
    const auto P = io::readNicrExtrinsicsJson(dir / "e.json");
    ASSERT_TRUE(P.has_value());
    EXPECT_TRUE(P->isApprox(T, 1e-12));
}

TEST(AtomicFile, NoTemporariesAndErrorsNameTheFile)
{
    const test::TempDir dir("atomic");
    writeFileAtomic(dir / "sub/a.txt", std::string("hello"));
    EXPECT_EQ(test::readBytes(dir / "sub/a.txt"), "hello");
    size_t files = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir.path)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u);
    // A failing producer leaves neither the file nor a temporary.
    EXPECT_THROW(writeFileAtomic(dir / "b.txt", [](std::ostream&) { throw std::runtime_error("boom"); }),
                 std::runtime_error);
    EXPECT_FALSE(fs::exists(dir / "b.txt"));
    files = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir.path)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u);
    // Unwritable target: a regular file where a folder should be.
    writeFileAtomic(dir / "blocker", std::string("x"));
    try
    {
        writeFileAtomic(dir / "blocker/c.txt", std::string("y"));
        FAIL() << "expected an error";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("blocker/c.txt"), std::string::npos) << e.what();
    }
}

TEST(AtomicFile, AWriteThatMeetsAFullDiskSaysWhy)
{
    // A file size limit fails writes with EFBIG as a full disk fails them with
    // ENOSPC (SIGXFSZ ignored): the message names the file and the reason.
    const test::TempDir dir("atomic_full");
    std::string what;
    {
        const test_support::FileSizeLimit full(1000);
        try
        {
            writeFileAtomic(dir / "big.txt", std::string(20000, 'x'));
        }
        catch (const std::runtime_error& e)
        {
            what = e.what();
        }
    }
    EXPECT_NE(what.find("big.txt"), std::string::npos) << what;
    EXPECT_NE(what.find(std::strerror(EFBIG)), std::string::npos) << what;
    EXPECT_TRUE(fs::is_empty(dir.path));
}

namespace
{
/// Two frames of a wall patch 1 m in front of the camera, labelled `sem`.
void addWall(GtCloudBuilder& b, uint16_t sem, uint32_t ins, int w = 200)
{
    const CameraIntrinsics K = test::smallK(w, w);
    const Image<float> depth(w, w, 1.0f);
    const FrameGeometry geo = computeFrameGeometry(depth, K, Pose::Identity());
    b.add(depth, geo, Image<uint16_t>(w, w, sem), Image<uint32_t>(w, w, ins));
}
}  // namespace

TEST(GtCloud, VoxelGridWithMajorityLabels)
{
    GtCloudBuilder b(0.01, 20.0);
    addWall(b, 5, 7);
    addWall(b, 5, 7);
    addWall(b, 1, 0);  // fewer votes
    const auto pts = b.build();
    ASSERT_FALSE(pts.empty());
    EXPECT_EQ(pts.size(), b.voxels());
    // 200 px at f = 180.6 (5.5 mm per pixel) cover 1.1 m x 1.1 m: ~110 x 110 voxels of 1 cm.
    EXPECT_GT(pts.size(), 9000u);
    EXPECT_LT(pts.size(), 14000u);
    for (const auto& p : pts)
    {
        EXPECT_EQ(p.label, (5u << 16) | 7u);
        EXPECT_NEAR(p.position.z(), 1.0f, 1e-5f);
        EXPECT_NEAR(p.normal.z(), -1.0f, 1e-4f);  // facing the camera
    }
    GtCloudBuilder far(0.01, 0.5);  // max depth below the wall: nothing
    addWall(far, 5, 7);
    EXPECT_EQ(far.voxels(), 0u);
}

TEST(GtWriters, PlyAndBenchmarkFilesAgree)
{
    const test::TempDir dir("ply");
    std::vector<GtPoint> pts(3);
    pts[0].label = (1u << 16);
    pts[1].label = (5u << 16) | 3u;
    pts[2].label = (40u << 16) | 65535u;
    pts[2].position = {1.5f, -2.f, 0.25f};
    pts[2].rgb = {10, 20, 30};
    writeGtPly(dir / "b.ply", pts, true);
    writeGtPly(dir / "a.ply", pts, false);
    const std::string bin = test::readBytes(dir / "b.ply");
    const size_t end = bin.find("end_header\n");
    ASSERT_NE(end, std::string::npos);
    EXPECT_NE(bin.find("format binary_little_endian 1.0"), std::string::npos);
    EXPECT_NE(bin.find("element vertex 3"), std::string::npos);
    EXPECT_NE(bin.find("property uint label"), std::string::npos);
    EXPECT_EQ(bin.size() - (end + 11), 3u * 31u);
    uint32_t label;
    float x;
    std::memcpy(&label, bin.data() + end + 11 + 2 * 31 + 27, 4);
    std::memcpy(&x, bin.data() + end + 11 + 2 * 31, 4);
    EXPECT_EQ(label, pts[2].label);
    EXPECT_EQ(x, 1.5f);
    const std::string ascii = test::readBytes(dir / "a.ply");
    EXPECT_NE(ascii.find("1.500000 -2.000000 0.250000 0.00000 0.00000 0.00000 10 20 30 2686975\n"), std::string::npos);

    const auto files = writeBenchmarkGt(dir / "bench", "scene_cam", pts);
    ASSERT_EQ(files.size(), 3u);
    EXPECT_EQ(test::readBytes(files[0]), "1\n5\n40\n");
    EXPECT_EQ(test::readBytes(files[1]), "65536\n327683\n2686975\n");
    EXPECT_EQ(test::readBytes(files[2]), test::readBytes(files[1]));
    EXPECT_EQ(gtPlyFileName(0.01, 20.0), "voxel_0_01_maxdepth_20_0.ply");
    EXPECT_EQ(gtPlyFileName(0.01, 10.0), "voxel_0_01_maxdepth_10_0.ply");
}
