// Sequence readers on synthetic folders: a world point seen from two cameras must land at the same
// world position after depth decoding, unprojection and the reader's camera→world pose.
#include "io_test_util.h"

#include <pndt/io/npz.h>
#include <pndt/io/pose_interpolator.h>
#include <pndt/io/sequence.h>

#include <cmath>
#include <sstream>

namespace pndt::io::test
{
namespace
{
constexpr int kW = 64, kH = 48;

CameraIntrinsics smallK()
{
    CameraIntrinsics K;
    K.width = kW;
    K.height = kH;
    K.fx = 50;
    K.fy = 50;
    K.cx = 31.5;
    K.cy = 23.5;
    return K;
}

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

/// One observation: the world point is seen at pixel (col,row) with depth_mm from pose T.
struct View
{
    int col, row;
    int depth_mm;
    Pose T_world_cam;
};

/// Two views of the same world point: the second pose is built so that the point projects
/// exactly onto its pixel at its depth (exact integer millimetres in both depth images).
std::vector<View> twoViewsOfOnePoint(Eigen::Vector3d& world_point)
{
    const CameraIntrinsics K = smallK();
    View a{40, 10, 2345, makePose(0.5, -1.0, 1.2, 0.3, -0.2, 0.9)};
    world_point = a.T_world_cam * K.unproject(a.col, a.row, a.depth_mm / 1000.0);
    View b{5, 30, 1500, makePose(0, 0, 0, -0.4, 0.5, -1.3)};
    b.T_world_cam.translation() = world_point - b.T_world_cam.linear() * K.unproject(b.col, b.row, 1.5);
    return {a, b};
}

cv::Mat depthWithOnePixel(int col, int row, uint16_t value)
{
    cv::Mat m(kH, kW, CV_16UC1, cv::Scalar(0));
    m.at<uint16_t>(row, col) = value;
    return m;
}

/// Unprojects every valid depth pixel of a loaded frame into the world.
std::vector<Eigen::Vector3d> worldPoints(const RgbdFrame& f)
{
    std::vector<Eigen::Vector3d> pts;
    for (int r = 0; r < f.depth.height; ++r)
        for (int c = 0; c < f.depth.width; ++c)
            if (f.depth.at(r, c) > 0) pts.push_back(*f.T_world_cam * f.K.unproject(c, r, f.depth.at(r, c)));
    return pts;
}

std::string logBlock(int i, const Pose& T)
{
    std::ostringstream s;
    s << i << " " << i << " " << i + 1 << "\n";
    for (int r = 0; r < 4; ++r)
        s << num(T.matrix()(r, 0)) << " " << num(T.matrix()(r, 1)) << " " << num(T.matrix()(r, 2)) << " "
          << num(T.matrix()(r, 3)) << "\n";
    return s.str();
}

std::string nicrPoseJson(const Pose& T)
{
    const Eigen::Quaterniond q(T.rotation());
    return "{\"x\": " + num(T.translation().x()) + ", \"y\": " + num(T.translation().y()) +
           ", \"z\": " + num(T.translation().z()) + ", \"quat_x\": " + num(q.x()) +
           ", \"quat_y\": " + num(q.y()) + ", \"quat_z\": " + num(q.z()) + ", \"quat_w\": " + num(q.w()) + "}";
}
}  // namespace

using Sequences = TempDirTest;

TEST_F(Sequences, RedwoodPointSeenFromTwoPosesLandsAtTheSameWorldPosition)
{
    Eigen::Vector3d P;
    auto views = twoViewsOfOnePoint(P);
    views.push_back({63, 47, 1000, Pose::Identity()});  // axis check: bottom-right pixel
    std::string log;
    for (size_t i = 0; i < views.size(); ++i)
    {
        char name[32];
        std::snprintf(name, sizeof(name), "%05zu.png", i);
        writePng16(path(std::string("depth/") + name),
                   depthWithOnePixel(views[i].col, views[i].row, static_cast<uint16_t>(views[i].depth_mm)));
        cv::Mat c(kH, kW, CV_8UC3, cv::Scalar(10.0 * i, 20, 30));  // B = 10 i
        cv::imwrite(path(std::string("image/") + name), c);
        log += logBlock(static_cast<int>(i), views[i].T_world_cam);
    }
    write("trajectory.log", log);
    write("camera_primesense.json",
          R"({"width": 64, "height": 48, "intrinsic_matrix": [50, 0, 0, 0, 50, 0, 31.5, 23.5, 1]})");

    const RgbdSequence seq = openRedwoodSequence(dir());
    ASSERT_EQ(seq.size(), 3u);
    EXPECT_EQ(seq.kind, "redwood");
    EXPECT_EQ(seq.frames_without_pose, 0u);
    for (size_t i = 0; i < 2; ++i)
    {
        const RgbdFrame f = seq.load(i);
        EXPECT_EQ(f.id, i == 0 ? "00000" : "00001");
        EXPECT_DOUBLE_EQ(f.t, i / 30.0);
        EXPECT_DOUBLE_EQ(f.K.fx, 50.0);
        EXPECT_DOUBLE_EQ(f.K.cy, 23.5);
        ASSERT_TRUE(f.T_world_cam.has_value());
        ASSERT_EQ(f.color.width, kW);
        EXPECT_EQ(f.color.at(0, 0), (std::array<uint8_t, 3>{30, 20, static_cast<uint8_t>(10 * i)}));
        const auto pts = worldPoints(f);
        ASSERT_EQ(pts.size(), 1u);
        EXPECT_LT((pts[0] - P).norm(), 1e-5) << "frame " << i << ": " << pts[0].transpose() << " vs " << P.transpose();
    }
    // Optical axes with identity pose: right of and below the principal point → +x, +y; depth → +z.
    const auto pts = worldPoints(seq.load(2));
    ASSERT_EQ(pts.size(), 1u);
    EXPECT_NEAR(pts[0].x(), (63 - 31.5) / 50.0, 1e-9);
    EXPECT_NEAR(pts[0].y(), (47 - 23.5) / 50.0, 1e-9);
    EXPECT_NEAR(pts[0].z(), 1.0, 1e-9);
    // Without colour.
    EXPECT_TRUE(seq.load(0, FrameLoadOptions{false, false, false}).color.empty());
    EXPECT_THROW(seq.load(3), std::out_of_range);
}

TEST_F(Sequences, RedwoodErrorsAndNonFinitePoses)
{
    writePng16(path("depth/00000.png"), depthWithOnePixel(1, 1, 1000));
    writePng16(path("depth/00001.png"), depthWithOnePixel(1, 1, 1000));
    EXPECT_INPUT_ERROR(openRedwoodSequence(dir()), "camera_primesense.json");
    write("camera_primesense.json", R"({"width": 64, "height": 48, "intrinsic_matrix": [50, 0, 0, 0, 50, 0, 31.5, 23.5, 1]})");
    write("trajectory.log", logBlock(0, Pose::Identity()));
    EXPECT_INPUT_ERROR(openRedwoodSequence(dir()), "trajectory.log", "has 1 poses", "2 frames");
    write("trajectory.log", logBlock(0, Pose::Identity()) + "1 1 2\nnan 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
    const RgbdSequence seq = openRedwoodSequence(dir());
    EXPECT_EQ(seq.frames_without_pose, 1u);
    EXPECT_EQ(seq.non_finite_poses, 1u);
    EXPECT_FALSE(seq.frames[1].T_world_cam.has_value());
    RedwoodOptions strict;
    strict.non_finite_pose_is_error = true;
    EXPECT_INPUT_ERROR(openRedwoodSequence(dir(), strict), "trajectory.log", "line 6", "non-finite");
    // Intrinsics that disagree with the image size are caught on load.
    RedwoodOptions wrongK;
    wrongK.intrinsics = smallK().scaled(2.0);
    EXPECT_INPUT_ERROR(openRedwoodSequence(dir(), wrongK).load(0), "00000.png", "64 x 48", "128 x 96");
    // Unequal colour count.
    cv::imwrite(path("color/00000.jpg"), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(1, 2, 3)));
    EXPECT_INPUT_ERROR(openRedwoodSequence(dir()), "2 depth images but 1 colour");
    EXPECT_INPUT_ERROR(openRedwoodSequence(dir() + "/none"), "none", "not found");
}

TEST_F(Sequences, Open3dRgbdMatchDefinesFrames)
{
    writePng16(path("depth/a.png"), depthWithOnePixel(1, 1, 1000));
    writePng16(path("depth/b.png"), depthWithOnePixel(2, 2, 2000));
    cv::imwrite(path("color/x.jpg"), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(1, 2, 3)));
    cv::imwrite(path("color/y.jpg"), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(1, 2, 3)));
    write("rgbd.match", "depth/b.png color/y.jpg\ndepth/a.png color/x.jpg\n");
    RedwoodOptions o;
    o.intrinsics = smallK();
    o.trajectory_file = "";
    const RgbdSequence seq = openRedwoodSequence(dir(), o);
    ASSERT_EQ(seq.size(), 2u);
    EXPECT_EQ(seq.frames[0].id, "b");
    EXPECT_NE(seq.frames[1].color_path.find("x.jpg"), std::string::npos);
    EXPECT_EQ(seq.frames_without_pose, 2u);
    EXPECT_FLOAT_EQ(seq.load(0).depth.at(2, 2), 2.0f);
    write("rgbd.match", "depth/b.png color/missing.jpg\n");
    EXPECT_INPUT_ERROR(openRedwoodSequence(dir(), o), "rgbd.match", "line 1", "missing.jpg");
}

TEST_F(Sequences, TumAssociatesStampsScalesDepthAndInterpolatesPoses)
{
    const double td[] = {100.000000, 100.033333, 100.066667, 105.0};
    std::string rgb_txt = "# color images\n# timestamp filename\n", depth_txt = "# depth maps\n";
    for (size_t i = 0; i < 4; ++i)
    {
        const std::string d = "depth/" + num(td[i]) + ".png", c = "rgb/" + num(td[i] + 0.004) + ".png";
        writePng16(path(d), depthWithOnePixel(3, 4, static_cast<uint16_t>(5000 + i)));
        cv::imwrite(path(c), cv::Mat(kH, kW, CV_8UC3, cv::Scalar(0, 0, 10.0 * i)));
        rgb_txt += num(td[i] + 0.004) + " " + c + "\n";
        depth_txt += num(td[i]) + " " + d + "\n";
    }
    // An unmatched colour image 0.5 s later must be ignored.
    cv::imwrite(path("rgb/200.png"), cv::Mat(kH, kW, CV_8UC3));
    rgb_txt += "100.5 rgb/200.png\n";
    write("rgb.txt", rgb_txt);
    write("depth.txt", depth_txt);
    const Pose Ta = makePose(1, 2, 3, 0, 0, 0.2), Tb = makePose(1.2, 2, 3, 0.1, 0, 0.4);
    auto tumLine = [&](double t, const Pose& T) {
        const Eigen::Quaterniond q(T.rotation());
        return num(t) + " " + num(T.translation().x()) + " " + num(T.translation().y()) + " " +
               num(T.translation().z()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z()) + " " + num(q.w()) + "\n";
    };
    write("groundtruth.txt", "# ground truth trajectory\n" + tumLine(99.99, Ta) + tumLine(100.08, Tb));

    TumOptions o;
    o.intrinsics = smallK();
    const RgbdSequence seq = openTumSequence(dir(), o);
    ASSERT_EQ(seq.size(), 4u);
    EXPECT_EQ(seq.kind, "tum");
    EXPECT_DOUBLE_EQ(seq.frames[1].t, 100.033333);
    EXPECT_EQ(seq.frames_without_pose, 1u);  // 105.0 is after the ground truth
    EXPECT_FALSE(seq.frames[3].T_world_cam.has_value());
    const Pose expected = interpolatePose(Ta, Tb, (100.033333 - 99.99) / (100.08 - 99.99));
    ASSERT_TRUE(seq.frames[1].T_world_cam.has_value());
    EXPECT_TRUE(seq.frames[1].T_world_cam->matrix().isApprox(expected.matrix(), 1e-9));

    const RgbdFrame f = seq.load(1);
    EXPECT_FLOAT_EQ(f.depth.at(4, 3), 5001.0f / 5000.0f);  // TUM: 5000 units per metre
    EXPECT_EQ(f.color.at(0, 0)[0], 10);                     // paired with the colour image of frame 1

    // 4-column association file (associate.py rgb.txt depth.txt) and depth-first order.
    write("associations.txt", num(td[0] + 0.004) + " rgb/" + num(td[0] + 0.004) + ".png " + num(td[0]) + " depth/" + num(td[0]) + ".png\n" +
                                  num(td[1]) + " depth/" + num(td[1]) + ".png " + num(td[1] + 0.004) + " rgb/" + num(td[1] + 0.004) + ".png\n");
    const RgbdSequence a = openTumSequence(dir(), o);
    ASSERT_EQ(a.size(), 2u);
    EXPECT_DOUBLE_EQ(a.frames[0].t, td[0]);
    EXPECT_DOUBLE_EQ(a.frames[1].t, td[1]);
    EXPECT_NE(a.frames[1].depth_path.find("depth/"), std::string::npos);
    EXPECT_DOUBLE_EQ(openTumSequence(dir()).frames[0].K.fx, 525.0);  // TUM default intrinsics

    // Lines out of time order or repeated: named, with both lines.
    const std::string line0 = num(td[0] + 0.004) + " rgb/" + num(td[0] + 0.004) + ".png " + num(td[0]) + " depth/" + num(td[0]) + ".png\n";
    const std::string line1 = num(td[1] + 0.004) + " rgb/" + num(td[1] + 0.004) + ".png " + num(td[1]) + " depth/" + num(td[1]) + ".png\n";
    write("associations.txt", line1 + line0);
    EXPECT_INPUT_ERROR(openTumSequence(dir(), o), "associations.txt", "line 2", "is not after the one of line 1");
    write("associations.txt", line0 + line1 + line1);
    EXPECT_INPUT_ERROR(openTumSequence(dir(), o), "associations.txt", "line 3", "in time order");

    // The layout the tools tell by (io::openRecordingFolder): an association file is TUM's.
    write("associations.txt", line0 + line1);
    EXPECT_TRUE(isTumFolder(dir()));
    EXPECT_EQ(openRecordingFolder(dir()).kind, "tum");
    std::filesystem::remove(path("rgb.txt"));
    EXPECT_TRUE(isTumFolder(dir())) << "associations.txt alone";
    std::filesystem::remove(path("associations.txt"));
    EXPECT_FALSE(isTumFolder(dir())) << "depth.txt alone";

    write("associations.txt", "1 rgb/x.png\n");
    EXPECT_INPUT_ERROR(openTumSequence(dir(), o), "associations.txt", "line 1", "not found");
    write("associations.txt", "1 rgb/x.png 2\n");
    EXPECT_INPUT_ERROR(openTumSequence(dir(), o), "associations.txt", "line 1", "got 3");
}

TEST_F(Sequences, NicrLayoutWithLabelsPredictionsAndUnregisteredColour)
{
    const std::string split = dir() + "/valid";
    const std::string seq_id = "ai_001_001/cam_00";
    Eigen::Vector3d P;
    const auto views = twoViewsOfOnePoint(P);
    const CameraIntrinsics K = smallK();
    write("valid/depth_intrinsics/" + seq_id + ".json",
          "{\"fx\": " + num(K.fx / kW) + ", \"fy\": " + num(K.fy / kH) + ", \"cx\": " + num(K.cx / kW) +
              ", \"cy\": " + num(K.cy / kH) + ", \"a\": 0.001, \"b\": -1}");
    write("valid/rgb_intrinsics/" + seq_id + ".json",
          "{\"fx\": " + num(K.fx / kW) + ", \"fy\": " + num(K.fy / kH) + ", \"cx\": " + num(K.cx / kW) +
              ", \"cy\": " + num(K.cy / kH) + "}");
    for (int i = 0; i < 3; ++i)
    {
        char stem[16];
        std::snprintf(stem, sizeof(stem), "%04d", i);
        const View& v = views[std::min(i, 1)];
        writePng16(path("valid/depth/" + seq_id + "/" + stem + ".png"),
                   depthWithOnePixel(v.col, v.row, static_cast<uint16_t>(v.depth_mm)));
        cv::imwrite(path("valid/rgb/" + seq_id + "/" + stem + ".png"), cv::Mat(2 * kH, 2 * kW, CV_8UC3, cv::Scalar(1, 2, 3)));
        write("valid/extrinsics/" + seq_id + "/" + stem + ".json",
              i < 2 ? nicrPoseJson(v.T_world_cam)
                    : R"({"x": NaN, "y": NaN, "z": NaN, "quat_x": NaN, "quat_y": NaN, "quat_z": NaN, "quat_w": NaN})");
    }
    cv::Mat sem(kH, kW, CV_8UC1, cv::Scalar(1));
    sem.at<uint8_t>(10, 40) = 5;
    cv::imwrite(path("valid/semantic_40/" + seq_id + "/0000.png"), sem);
    cv::Mat inst(kH, kW, CV_8UC3, cv::Scalar(0, 0, 0));
    inst.at<cv::Vec3b>(10, 40) = cv::Vec3b(3, 1, 5);  // B=3, G=1 → id 259; R = class 5
    cv::imwrite(path("valid/instance/" + seq_id + "/0000.png"), inst);
    std::vector<float> ps(kW * kH, 1.75f), pi(kW * kH, 0.0f);
    ps[10 * kW + 40] = 5.5f;
    pi[10 * kW + 40] = 259.25f;
    ZipMember zs{"arr_0.npy", makeNpy("<f4", "(1, 48, 64)", floatBytes(ps))}, zi{"arr_0.npy", makeNpy("<f4", "(48, 64)", floatBytes(pi))};
    zs.deflate = zi.deflate = true;
    zs.zip64_local = zi.zip64_local = true;
    write("pred/pred_panoptic_semantic/" + seq_id + "/0000.npz", makeZip({zs}));
    write("pred/pred_panoptic_instance/" + seq_id + "/0000.npz", makeZip({zi}));

    EXPECT_EQ(listNicrSequences(split), std::vector<std::string>{seq_id});
    NicrOptions o;
    o.predictions_dir = dir() + "/pred";
    const RgbdSequence seq = openNicrSequence(split, seq_id, o);
    ASSERT_EQ(seq.size(), 3u);
    EXPECT_EQ(seq.kind, "nicr");
    EXPECT_DOUBLE_EQ(seq.depth_units_per_metre, 1000.0);  // from a = 0.001
    EXPECT_EQ(seq.frames_without_pose, 1u);
    EXPECT_EQ(seq.non_finite_poses, 1u);
    EXPECT_DOUBLE_EQ(seq.frames[1].t, 1.0 / 30.0);
    EXPECT_EQ(seq.frames[2].id, "0002");

    for (size_t i = 0; i < 2; ++i)
    {
        const RgbdFrame f = seq.load(i);
        EXPECT_NEAR(f.K.fx, 50.0, 1e-9);
        EXPECT_NEAR(f.K.cx, 31.5, 1e-9);
        EXPECT_NEAR(f.K.cy, 23.5, 1e-9);
        EXPECT_EQ(f.K.width, kW);
        // Colour is twice the depth size; its intrinsics follow the colour image.
        EXPECT_EQ(f.color.width, 2 * kW);
        EXPECT_EQ(f.K_color.width, 2 * kW);
        EXPECT_NEAR(f.K_color.fx, 100.0, 1e-9);
        const auto pts = worldPoints(f);
        ASSERT_EQ(pts.size(), 1u);
        EXPECT_LT((pts[0] - P).norm(), 1e-5) << "frame " << i;
    }
    const RgbdFrame f0 = seq.load(0);
    ASSERT_FALSE(f0.semantic_gt.empty());
    EXPECT_EQ(f0.semantic_gt.at(10, 40), 5);
    EXPECT_EQ(f0.instance_gt.at(10, 40), 259);
    ASSERT_FALSE(f0.pred_semantic.empty());
    const auto ds = decodeIdScore(f0.pred_semantic), di = decodeIdScore(f0.pred_instance);
    EXPECT_EQ(ds.ids.at(10, 40), 5);
    EXPECT_FLOAT_EQ(ds.scores.at(10, 40), 0.5f);
    EXPECT_EQ(ds.ids.at(0, 0), 1);
    EXPECT_EQ(di.ids.at(10, 40), 259);
    EXPECT_FLOAT_EQ(di.scores.at(10, 40), 0.25f);
    EXPECT_TRUE(seq.load(1).semantic_gt.empty());  // no GT file for frame 1

    NicrOptions no_labels;
    no_labels.semantic_dir = "-";
    no_labels.instance_dir = "-";
    EXPECT_TRUE(openNicrSequence(split, seq_id, no_labels).frames[0].semantic_path.empty());

    // An instance image of another size than its semantic image: an error naming it (pndt-map
    // wrote past the end of its instance image, pndt-eval read past the end of this one).
    {
        const std::string inst_path = path("valid/instance/" + seq_id + "/0000.png");
        cv::imwrite(inst_path, cv::Mat(kH / 2, kW / 2, CV_8UC3, cv::Scalar(0, 0, 0)));
        EXPECT_INPUT_ERROR(seq.load(0), "instance/ai_001_001/cam_00/0000.png",
                           "ground-truth instance image is 32 x 24 but its semantic image");
        FrameLoadOptions geometry_only;
        geometry_only.labels = false;
        geometry_only.predictions = false;
        EXPECT_NO_THROW(seq.load(0, geometry_only));
        cv::imwrite(inst_path, inst);
        ZipMember small{"arr_0.npy", makeNpy("<f4", "(24, 32)", floatBytes(std::vector<float>(32 * 24, 0.f)))};
        write("pred/pred_panoptic_instance/" + seq_id + "/0000.npz", makeZip({small}));
        EXPECT_INPUT_ERROR(seq.load(0), "pred_panoptic_instance/ai_001_001/cam_00/0000.npz",
                           "predicted instance image is 32 x 24 but its semantic image");
    }

    EXPECT_INPUT_ERROR(openNicrSequence(split, "ai_009_009/cam_00"), "ai_009_009/cam_00", "not found");
    std::filesystem::remove(path("valid/depth_intrinsics/" + seq_id + ".json"));
    EXPECT_INPUT_ERROR(openNicrSequence(split, seq_id), "cam_00.json", "depth intrinsics file not found");
}

}  // namespace pndt::io::test
