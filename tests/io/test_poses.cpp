// Pose-file readers: values, frame conventions, cross-format agreement and error reporting.
#include "io_test_util.h"

#include <pndt/io/poses.h>

#include <cmath>
#include <sstream>

namespace pndt::io::test
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

Pose makePose(double x, double y, double z, double roll, double pitch, double yaw)
{
    Pose T = Pose::Identity();
    T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(x, y, z);
    return T;
}

std::string num(double v)
{
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.12f", v);
    return buf;
}

/// "x y z qx qy qz qw"
std::string tq(const Pose& T)
{
    const Eigen::Quaterniond q(T.rotation());
    const Eigen::Vector3d t = T.translation();
    return num(t.x()) + " " + num(t.y()) + " " + num(t.z()) + " " + num(q.x()) + " " + num(q.y()) +
           " " + num(q.z()) + " " + num(q.w());
}

/// "r11 r12 r13 tx r21 ... tz"
std::string m34(const Pose& T)
{
    std::string s;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) s += (s.empty() ? "" : " ") + num(T.matrix()(r, c));
    return s;
}

void expectPoseNear(const Pose& a, const Pose& b, double tol = 1e-9)
{
    EXPECT_TRUE(a.matrix().isApprox(b.matrix(), tol) || (a.matrix() - b.matrix()).norm() < tol)
        << "a=\n"
        << a.matrix() << "\nb=\n"
        << b.matrix();
}

const std::vector<Pose>& samplePoses()
{
    static const std::vector<Pose> poses = {
        Pose::Identity(),
        makePose(1.0, -2.0, 0.5, 0.1, -0.2, 0.3),
        makePose(-3.25, 0.75, 1.5, -0.4, 0.25, 2.9),
    };
    return poses;
}
}  // namespace

using PoseFiles = TempDirTest;

TEST_F(PoseFiles, TumValuesCommentsAndBlankLines)
{
    const Pose T = makePose(1, 2, 3, 0, 0, kPi / 2);
    const std::string p = write("gt.txt", "# ground truth\n# timestamp tx ty tz qx qy qz qw\n\n"
                                          "1305031102.175304 " + tq(Pose::Identity()) + "\n"
                                          "1305031102.185304 " + tq(T) + "\r\n");
    const auto poses = readTumPoses(p);
    ASSERT_EQ(poses.size(), 2u);
    EXPECT_DOUBLE_EQ(poses[0].t, 1305031102.175304);
    EXPECT_DOUBLE_EQ(poses[1].t, 1305031102.185304);
    expectPoseNear(poses[1].T_world_sensor, T);
    // 90° yaw: the sensor x axis points along world y.
    EXPECT_TRUE((poses[1].T_world_sensor.rotation() * Eigen::Vector3d::UnitX())
                    .isApprox(Eigen::Vector3d::UnitY(), 1e-9));
}

TEST_F(PoseFiles, TumAndRtabmap10And11Agree)
{
    std::string tum, r10 = "#timestamp x y z qx qy qz qw\n", r11 = "#timestamp x y z qx qy qz qw id\n";
    for (size_t i = 0; i < samplePoses().size(); ++i)
    {
        const std::string line = num(100.0 + 0.1 * i) + " " + tq(samplePoses()[i]);
        tum += line + "\n";
        r10 += line + "\n";
        r11 += line + " " + std::to_string(i + 1) + "\n";
    }
    const auto a = readPoseFile(write("a.txt", tum), PoseFormat::Tum);
    const auto b = readPoseFile(write("b.txt", r10), PoseFormat::Rtabmap10);
    const auto c = readPoseFile(write("c.txt", r11), PoseFormat::Rtabmap11);
    ASSERT_EQ(a.size(), 3u);
    ASSERT_EQ(b.size(), 3u);
    ASSERT_EQ(c.size(), 3u);
    for (size_t i = 0; i < 3; ++i)
    {
        EXPECT_EQ(a[i].t, b[i].t);
        EXPECT_EQ(a[i].t, c[i].t);
        EXPECT_EQ(a[i].T_world_sensor.matrix(), b[i].T_world_sensor.matrix());
        EXPECT_EQ(a[i].T_world_sensor.matrix(), c[i].T_world_sensor.matrix());
        expectPoseNear(a[i].T_world_sensor, samplePoses()[i], 1e-9);
        EXPECT_EQ(c[i].id, static_cast<int64_t>(i + 1));
        EXPECT_EQ(a[i].id, -1);
    }
}

// RTAB-Map writes the same internal pose differently per format (Graph.cpp exportPoses); every
// reader must give back the internal pose.
TEST_F(PoseFiles, AllRtabmapFormatsRecoverTheSameInternalPose)
{
    Eigen::Matrix3d A;
    A << 0, 0, 1, 0, -1, 0, 1, 0, 0;
    Pose TA = Pose::Identity();
    TA.linear() = A;
    const Pose Tbo = bodyFromOptical(), Tob = opticalFromBody();

    std::string f0, f1, f2, f4 = "PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n", f10, f11;
    for (size_t i = 0; i < samplePoses().size(); ++i)
    {
        const Pose& T = samplePoses()[i];
        const std::string stamp = num(50.0 + i);
        f0 += m34(T) + "\n";
        f2 += m34(Tob * T * Tbo) + "\n";
        f1 += stamp + " " + tq(Tob * TA * T * Tbo) + "\n";
        f4 += "VERTEX_SE3:QUAT " + std::to_string(i + 1) + " " + tq(T) + "\n";
        f10 += stamp + " " + tq(T) + "\n";
        f11 += stamp + " " + tq(T) + " " + std::to_string(i + 1) + "\n";
    }
    f4 += "VERTEX_TRACKXYZ 7 1 2 3\nEDGE_SE3:QUAT 1 2 0 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\nFIX 1\n";

    const std::vector<std::pair<PoseFormat, std::string>> files = {
        {PoseFormat::Rtabmap0, write("f0.txt", f0)},    {PoseFormat::Rtabmap1, write("f1.txt", f1)},
        {PoseFormat::Rtabmap2, write("f2.txt", f2)},    {PoseFormat::Rtabmap4, write("f4.g2o", f4)},
        {PoseFormat::Rtabmap10, write("f10.txt", f10)}, {PoseFormat::Rtabmap11, write("f11.txt", f11)},
    };
    for (const auto& [fmt, p] : files)
    {
        SCOPED_TRACE(toString(fmt));
        const auto poses = readPoseFile(p, fmt);
        ASSERT_EQ(poses.size(), samplePoses().size());
        for (size_t i = 0; i < poses.size(); ++i) expectPoseNear(poses[i].T_world_sensor, samplePoses()[i], 1e-9);
    }
    // Stamps: line index for 0/2, vertex id for g2o, file stamps otherwise.
    EXPECT_EQ(readRtabmapPoses(files[0].second, 0)[2].t, 2.0);
    EXPECT_EQ(readRtabmapPoses(files[2].second, 2)[1].t, 1.0);
    EXPECT_EQ(readRtabmapPoses(files[3].second, 4)[2].t, 3.0);
    EXPECT_EQ(readRtabmapPoses(files[3].second, 4)[2].id, 3);
    EXPECT_EQ(readRtabmapPoses(files[1].second, 1)[1].t, 51.0);
}

TEST_F(PoseFiles, KittiIsReturnedAsStoredAndG2oSe2IsPlanar)
{
    const Pose T = makePose(0.5, 0.25, 4.0, 0.05, 0.6, -0.1);
    const auto k = readPoseFile(write("k.txt", m34(Pose::Identity()) + "\n" + m34(T) + "\n"), PoseFormat::Kitti);
    ASSERT_EQ(k.size(), 2u);
    expectPoseNear(k[1].T_world_sensor, T);
    EXPECT_EQ(k[1].t, 1.0);

    const auto g = readRtabmapPoses(write("g.g2o", "VERTEX_SE2 4 1.0 2.0 1.5707963267948966\n"), 4);
    ASSERT_EQ(g.size(), 1u);
    expectPoseNear(g[0].T_world_sensor, makePose(1, 2, 0, 0, 0, kPi / 2));
}

TEST(PoseAxes, BodyFromOpticalMapsOpticalAxesToRosAxes)
{
    const Pose T = bodyFromOptical();
    // optical z (forward) -> body x (forward); optical x (right) -> body -y; optical y (down) -> body -z
    EXPECT_TRUE((T * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX()));
    EXPECT_TRUE((T * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY()));
    EXPECT_TRUE((T * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ()));
    // Same as MRPT's CPose3D(0,0,0, yaw=-90°, pitch=0, roll=-90°) = Rz(yaw)·Ry(pitch)·Rx(roll).
    const Eigen::Matrix3d mrpt = (Eigen::AngleAxisd(-kPi / 2, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(-kPi / 2, Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
    EXPECT_TRUE(T.rotation().isApprox(mrpt, 1e-12));
    EXPECT_TRUE((opticalFromBody() * bodyFromOptical()).matrix().isIdentity(1e-12));
}

TEST_F(PoseFiles, RedwoodLogBlocksWithTabsAndSpaces)
{
    const Pose T = makePose(2, 2, -0.3, 0.2, 0.1, -0.5);
    std::ostringstream s;
    s << "0\t0\t1\n";
    const auto& M = T.matrix();
    for (int r = 0; r < 4; ++r) s << "   " << num(M(r, 0)) << "  " << num(M(r, 1)) << "\t" << num(M(r, 2)) << " " << num(M(r, 3)) << "\n";
    s << "1 1 2\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
    PoseReadOptions opt;
    opt.frame_rate_hz = 10.0;
    const auto poses = readPoseFile(write("t.log", s.str()), PoseFormat::Redwood, opt);
    ASSERT_EQ(poses.size(), 2u);
    expectPoseNear(poses[0].T_world_sensor, T);
    EXPECT_EQ(poses[1].T_world_sensor.matrix(), Eigen::Matrix4d::Identity());
    EXPECT_DOUBLE_EQ(poses[1].t, 0.1);
    EXPECT_EQ(poses[1].id, 1);
}

TEST_F(PoseFiles, NicrExtrinsicsFileAndFolder)
{
    const Pose T = makePose(0.1, 0.2, 0.3, 0.3, 0.2, 0.1);
    const Eigen::Quaterniond q(T.rotation());
    auto json = [&](const Pose& P) {
        const Eigen::Quaterniond qq(P.rotation());
        return "{\"x\": " + num(P.translation().x()) + ", \"y\": " + num(P.translation().y()) +
               ", \"z\": " + num(P.translation().z()) + ", \"quat_x\": " + num(qq.x()) +
               ", \"quat_y\": " + num(qq.y()) + ", \"quat_z\": " + num(qq.z()) +
               ", \"quat_w\": " + num(qq.w()) + "}";
    };
    const std::string single = write("one.json", json(T));
    auto p = readNicrExtrinsicsJson(single);
    ASSERT_TRUE(p.has_value());
    expectPoseNear(*p, T);

    write("ext/00000.json", json(Pose::Identity()));
    write("ext/00005.json", "{\"x\": NaN, \"y\": -Infinity, \"z\": 0, \"quat_x\": 0, \"quat_y\": 0, "
                            "\"quat_z\": 0, \"quat_w\": Infinity}");
    write("ext/00010.json", json(T));
    PoseReadReport report;
    const auto poses = readPoseFile(dir() + "/ext", PoseFormat::Nicr, {}, &report);
    ASSERT_EQ(poses.size(), 2u);
    EXPECT_EQ(poses[1].id, 10);
    EXPECT_DOUBLE_EQ(poses[1].t, 10.0 / 30.0);
    expectPoseNear(poses[1].T_world_sensor, T);
    EXPECT_EQ(report.skipped_non_finite, 1u);
    ASSERT_EQ(report.skipped_where.size(), 1u);
    EXPECT_NE(report.skipped_where[0].find("00005.json"), std::string::npos);

    PoseReadOptions strict;
    strict.non_finite_is_error = true;
    EXPECT_INPUT_ERROR(readNicrPoses(dir() + "/ext", strict), "00005.json", "non-finite");
    EXPECT_FALSE(readNicrExtrinsicsJson(dir() + "/ext/00005.json").has_value());
}

TEST_F(PoseFiles, NonFinitePosesAreSkippedAndCountedByDefault)
{
    const std::string p = write("nf.txt", "1.0 0 0 0 0 0 0 1\n2.0 nan 0 0 0 0 0 1\n3.0 0 0 inf 0 0 0 1\n4.0 1 0 0 0 0 0 1\n");
    PoseReadReport report;
    const auto poses = readTumPoses(p, {}, &report);
    ASSERT_EQ(poses.size(), 2u);
    EXPECT_EQ(poses[1].t, 4.0);
    EXPECT_EQ(report.skipped_non_finite, 2u);
    ASSERT_EQ(report.skipped_where.size(), 2u);
    EXPECT_NE(report.skipped_where[0].find("line 2"), std::string::npos);

    PoseReadOptions strict;
    strict.non_finite_is_error = true;
    EXPECT_INPUT_ERROR(readTumPoses(p, strict), "nf.txt", "line 2", "non-finite");

    // Stampless formats keep the index aligned: the skipped line still consumes index 1.
    const std::string raw = write("raw.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n-nan 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 5 0 1 0 0 0 0 1 0\n");
    const auto r = readRtabmapPoses(raw, 0);
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[1].t, 2.0);
    EXPECT_EQ(r[1].T_world_sensor.translation().x(), 5.0);

    // A non-finite stamp is always an error.
    EXPECT_INPUT_ERROR(readTumPoses(write("nfs.txt", "nan 0 0 0 0 0 0 1\n")), "nfs.txt", "line 1", "timestamp");
}

TEST_F(PoseFiles, MalformedLinesNameFileAndLine)
{
    EXPECT_INPUT_ERROR(readTumPoses(write("short.txt", "# c\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0\n")),
                       "short.txt", "line 3", "expected 8 values", "got 6");
    EXPECT_INPUT_ERROR(readTumPoses(write("nine.txt", "1 0 0 0 0 0 0 1 7\n")), "nine.txt", "line 1", "format 11");
    EXPECT_INPUT_ERROR(readTumPoses(write("word.txt", "1 0 0 0 0 0 0 1\n\n2 0 zero 0 0 0 0 1\n")),
                       "word.txt", "line 3", "'zero' is not a number");
    EXPECT_INPUT_ERROR(readTumPoses(write("zq.txt", "1 0 0 0 0 0 0 0\n")), "zq.txt", "line 1", "zero quaternion");
    EXPECT_INPUT_ERROR(readTumPoses(write("nq.txt", "1 0 0 0 0 0 0 2\n")), "nq.txt", "line 1", "non-unit quaternion");
    EXPECT_INPUT_ERROR(readRtabmapPoses(write("id.txt", "1 0 0 0 0 0 0 1 x7\n"), 11), "id.txt", "line 1", "not an integer");
    EXPECT_INPUT_ERROR(readRtabmapPoses(write("r0.txt", "1 0 0 0 0 1 0 0 0 0 1\n"), 0), "r0.txt", "line 1", "expected 12 values");
    EXPECT_INPUT_ERROR(readRtabmapPoses(write("scaled.txt", "2 0 0 0 0 2 0 0 0 0 2 0\n"), 2), "scaled.txt", "line 1", "not orthonormal");
    EXPECT_INPUT_ERROR(readKittiPoses(write("refl.txt", "\n-1 0 0 0 0 1 0 0 0 0 1 0\n")), "refl.txt", "line 2", "determinant");
    EXPECT_INPUT_ERROR(readRtabmapPoses(write("bad.g2o", "VERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\nfoo 1 2\n"), 4),
                       "bad.g2o", "line 2", "unknown g2o record 'foo'");
    EXPECT_INPUT_ERROR(readRtabmapPoses(write("dup.g2o", "VERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\n"), 4),
                       "dup.g2o", "line 2", "duplicate vertex id 1");
    EXPECT_INPUT_ERROR(readRtabmapPoses(write("short.g2o", "VERTEX_SE3:QUAT 1 0 0 0\n"), 4), "short.g2o", "line 1");
    EXPECT_INPUT_ERROR(readRtabmapPoses(write("x.txt", ""), 3), "x.txt", "unsupported RTAB-Map pose format 3");
}

TEST_F(PoseFiles, MalformedRedwoodLog)
{
    EXPECT_INPUT_ERROR(readRedwoodLog(write("trunc.log", "0 0 1\n1 0 0 0\n0 1 0 0\n")), "trunc.log", "line 4", "row 3 of 4 missing");
    EXPECT_INPUT_ERROR(readRedwoodLog(write("row.log", "0 0 1\n1 0 0 0\n0 1 0\n0 0 1 0\n0 0 0 1\n")), "row.log", "line 3", "expected 4 values");
    EXPECT_INPUT_ERROR(readRedwoodLog(write("last.log", "0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 1 1\n")), "last.log", "line 5", "0 0 0 1");
    EXPECT_INPUT_ERROR(readRedwoodLog(write("hdr.log", "0 0\n1 0 0 0\n")), "hdr.log", "line 1", "header");
    EXPECT_INPUT_ERROR(readRedwoodLog(write("rot.log", "0 0 1\n1 0 0 0\n0 1.5 0 0\n0 0 1 0\n0 0 0 1\n")), "rot.log", "line 2", "orthonormal");
    // A block left out (frame 1 missing): frame 2's pose was read as frame 1's, and so on.
    const std::string id = "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
    EXPECT_INPUT_ERROR(readRedwoodLog(write("gap.log", "0 0 1\n" + id + "2 2 3\n" + id)), "gap.log", "line 6",
                       "block 1 of the file has frame id 2", "a frame missing or out of order");
    EXPECT_INPUT_ERROR(readRedwoodLog(write("order.log", "1 1 2\n" + id + "0 0 1\n" + id)), "order.log", "line 1",
                       "block 0 of the file has frame id 1");
}

TEST_F(PoseFiles, MissingFileAndMalformedJson)
{
    EXPECT_INPUT_ERROR(readTumPoses(dir() + "/nope.txt"), "nope.txt", "file not found");
    EXPECT_INPUT_ERROR(readPoseFile(dir() + "/nope.log", PoseFormat::Redwood), "nope.log", "file not found");
    EXPECT_INPUT_ERROR(readNicrExtrinsicsJson(write("bad.json", "{\"x\": 1,\n \"y\": }\n")), "bad.json", "malformed JSON", "line 2");
    EXPECT_INPUT_ERROR(readNicrExtrinsicsJson(write("miss.json", "{\"x\":0,\"y\":0,\"z\":0,\"quat_x\":0,\"quat_y\":0,\"quat_z\":0}")),
                       "miss.json", "missing key 'quat_w'");
    EXPECT_INPUT_ERROR(readNicrExtrinsicsJson(write("str.json", "{\"x\":\"0\",\"y\":0,\"z\":0,\"quat_x\":0,\"quat_y\":0,\"quat_z\":0,\"quat_w\":1}")),
                       "str.json", "'x' is not a number");
    EXPECT_INPUT_ERROR(readNicrExtrinsicsJson(write("q.json", "{\"x\":0,\"y\":0,\"z\":0,\"quat_x\":0,\"quat_y\":0,\"quat_z\":0,\"quat_w\":0}")),
                       "q.json", "zero quaternion");
    EXPECT_INPUT_ERROR(readNicrPoses(write("nicr_empty/readme.txt", "x"), {}), "readme.txt");
}

TEST(PoseFormatNames, ParseAndRoundTrip)
{
    for (PoseFormat f : {PoseFormat::Tum, PoseFormat::Rtabmap0, PoseFormat::Rtabmap1, PoseFormat::Rtabmap2,
                         PoseFormat::Rtabmap4, PoseFormat::Rtabmap10, PoseFormat::Rtabmap11,
                         PoseFormat::Kitti, PoseFormat::Redwood, PoseFormat::Nicr})
        EXPECT_EQ(parsePoseFormat(toString(f)), f);
    EXPECT_EQ(parsePoseFormat("TUM"), PoseFormat::Tum);
    EXPECT_EQ(parsePoseFormat("RtabMap11"), PoseFormat::Rtabmap11);
    EXPECT_EQ(parsePoseFormat("g2o"), PoseFormat::Rtabmap4);
    EXPECT_EQ(parsePoseFormat("log"), PoseFormat::Redwood);
    EXPECT_INPUT_ERROR(parsePoseFormat("rtabmap3"), "'rtabmap3'", "rtabmap11");
    EXPECT_INPUT_ERROR(parsePoseFormat("colmap"), "unknown pose format 'colmap'");
}

}  // namespace pndt::io::test
