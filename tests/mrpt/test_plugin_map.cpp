// PanopticNDTMap as MRPT sees it: .ini construction, observation pairing,
// bad input, and the camera-pose convention against MRPT's own unprojection.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/T3DPointsProjectionParams.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/mrpt/observation_frame.h>

#include <cstring>

#include "observation_fixtures.h"

using namespace pndt;

namespace
{
const char* kIni = R"ini(
[MAP]
PanopticNDTMap_count=1

[MAP_PanopticNDTMap_00_creationOpts]
voxel_size=0.25
theta_z=0.4
use_ndt=true

[MAP_PanopticNDTMap_00_insertOpts]
label_pairing_tolerance=0.005

[MAP_PanopticNDTMap_00_renderOpts]
color_mode=semantic
shape=ellipsoids
)ini";

mrpt::maps::CMultiMetricMap multiMapFrom(const std::string& ini)
{
    mrpt::config::CConfigFileMemory cfg(ini);
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(cfg, "MAP");
    mrpt::maps::CMultiMetricMap mm;
    mm.setListOfMaps(inits);
    return mm;
}

/// What building a map from `ini` throws, or "no error".
std::string message(const std::string& ini)
{
    try
    {
        multiMapFrom(ini);
        return "no error";
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
}
}  // namespace

TEST(PluginIni, CMultiMetricMapBuildsTheMapFromAnIniString)
{
    auto mm = multiMapFrom(kIni);
    ASSERT_EQ(mm.maps.size(), 1u);
    auto m = mm.mapByClass<PanopticNDTMap>();
    ASSERT_TRUE(m);
    EXPECT_DOUBLE_EQ(m->core().options().voxel_size, 0.25);
    EXPECT_DOUBLE_EQ(m->core().options().theta_z, 0.4);
    EXPECT_DOUBLE_EQ(m->insertionOptions.label_pairing_tolerance, 0.005);
    EXPECT_EQ(m->renderOptions.color_mode, ColorMode::Semantic);
    EXPECT_EQ(m->renderOptions.shape, VoxelShape::Ellipsoids);
    EXPECT_EQ(std::string(m->GetRuntimeClass()->className), "pndt::PanopticNDTMap");
}

TEST(PluginIni, ThreadsKeyIsReadAndValidated)
{
    EXPECT_EQ(multiMapFrom(kIni).mapByClass<PanopticNDTMap>()->core().options().threads, 1);  // default
    std::string ini = kIni;
    ini.replace(ini.find("use_ndt=true"), 12, "use_ndt=true\nthreads=2");
    EXPECT_EQ(multiMapFrom(ini).mapByClass<PanopticNDTMap>()->core().options().threads, 2);
    for (const char* bad : {"threads=-1", "threads=300", "threads=two"})
    {
        std::string b = kIni;
        b.replace(b.find("use_ndt=true"), 12, std::string("use_ndt=true\n") + bad);
        try
        {
            multiMapFrom(b);
            ADD_FAILURE() << "no error for " << bad;
        }
        catch (const std::exception& e)
        {
            EXPECT_NE(std::string(e.what()).find("threads"), std::string::npos) << e.what();
        }
    }
}

TEST(PluginIni, UnknownOrMalformedKeysAreErrorsNamingThem)
{
    std::string ini = kIni;
    ini += "\n[MAP_PanopticNDTMap_00_creationOpts]\nvoxel_sise=0.1\n";
    try
    {
        multiMapFrom(ini);
        FAIL() << "expected an error";
    }
    catch (const std::exception& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("voxel_sise"), std::string::npos) << msg;
        EXPECT_NE(msg.find("MAP_PanopticNDTMap_00_creationOpts"), std::string::npos) << msg;
    }
    std::string bad = kIni;
    bad.replace(bad.find("theta_z=0.4"), 11, "theta_z=0.4x");
    try
    {
        multiMapFrom(bad);
        FAIL() << "expected an error";
    }
    catch (const std::exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("'0.4x'"), std::string::npos) << e.what();
    }
    // What MRPT prints keeps the section whole: it reads "[...]" in a message as a source
    // location ("Location: config [MAP_PanopticNDTMap_00_creationOpts", the rest lost).
    EXPECT_NE(message(ini).find("config section 'MAP_PanopticNDTMap_00_creationOpts': unknown key 'voxel_sise'"),
              std::string::npos)
        << message(ini);
    // A misspelt section, or one the plugin does not read, is not silently left at the defaults.
    for (const char* section : {"MAP_PanopticNDTMap_0_creationOpts", "MAP_PanopticNDTMap_00_creationOpt",
                                "MAP_PanopticNDTMap_00_likelihoodOpts"})
    {
        const std::string m = message(std::string(kIni) + "\n[" + section + "]\nvoxel_size=0.1\n");
        EXPECT_NE(m.find(std::string("config section '") + section + "' is not read by PanopticNDTMap"),
                  std::string::npos)
            << section << ": " << m;
    }
    EXPECT_NE(message(std::string(kIni) + "\n[MAP_PanopticNDTMap_00_likelihoodOpts]\n").find("set in code"),
              std::string::npos);
    // "voxel_size=" (a value lost in editing) is an error, not the default.
    std::string empty = kIni;
    empty.replace(empty.find("voxel_size=0.25"), 15, "voxel_size=");
    EXPECT_NE(message(empty).find("key 'voxel_size': value '' is not a number (to keep the default, remove the key)"),
              std::string::npos)
        << message(empty);
    // A rule's words come through whole (an interval "[0, 1]" at a message's end lost its "]"
    // and moved under "Location:").
    std::string theta = kIni;
    theta.replace(theta.find("theta_z=0.4"), 11, "theta_z=2.0");
    EXPECT_NE(message(theta).find("map option 'theta_z' must be between 0 and 1"), std::string::npos)
        << message(theta);
}

// A class set of one's own: its count, class 0 and names are checked, naming the key (256
// classes said only "a class set needs 1..255 classes"; class 0 "road" and two classes named
// "c5" were taken).
TEST(PluginIni, AClassSetOfOnesOwnIsCheckedNamingTheKey)
{
    const auto withClasses = [&](const std::string& names, const std::string& stuff) {
        std::string ini = kIni;
        ini.replace(ini.find("use_ndt=true"), 12,
                    "use_ndt=true\nclass_names=" + names + (stuff.empty() ? "" : "\nstuff_classes=" + stuff));
        return ini;
    };
    const std::string key = "config section 'MAP_PanopticNDTMap_00_creationOpts', key 'class_names': ";
    std::string many = "void";
    for (int i = 1; i < 256; ++i) many += ",c" + std::to_string(i);
    EXPECT_NE(message(withClasses(many, "")).find(key + "a class set holds 1 to 255 classes (class 0 = void), not 256"),
              std::string::npos)
        << message(withClasses(many, ""));
    EXPECT_NE(message(withClasses("road,wall,chair", "road,wall")).find(key + "class 0 must be 'void'"),
              std::string::npos);
    EXPECT_NE(message(withClasses("void,wall,c5,chair,c5", "")).find(key + "class name 'c5' is given twice (classes 2 "
                                                                         "and 4)"),
              std::string::npos)
        << message(withClasses("void,wall,c5,chair,c5", ""));
    // A good one is read, void stuff even when stuff_classes leaves it out.
    auto mm = multiMapFrom(withClasses("void,wall,floor,chair,table", "wall,floor"));
    const ClassSet& c = mm.mapByClass<PanopticNDTMap>()->core().options().classes;
    ASSERT_EQ(c.size(), 5u);
    EXPECT_FALSE(c.isThing(0));
    EXPECT_FALSE(c.isThing(1));
    EXPECT_TRUE(c.isThing(3));
    EXPECT_EQ(c.find("table"), 4);
}

TEST(PluginPose, CameraConventionAgreesWithMrptUnprojection)
{
    auto scan = fixtures::wallScan(0.0, 2.0f);
    // Vary the depth so the check is not degenerate.
    for (int r = 0; r < fixtures::kH; ++r)
        for (int c = 0; c < fixtures::kW; ++c) scan->rangeImage(r, c) = uint16_t(1500 + 10 * r + 3 * c);
    scan->sensorPose = mrpt::poses::CPose3D(0.1, -0.2, 1.2, 0.3, -0.1, 0.05);
    const mrpt::poses::CPose3D robot(2.0, 1.0, 0.0, 0.7, 0.0, 0.0);

    mrpt::maps::CSimplePointsMap pts;
    mrpt::obs::T3DPointsProjectionParams pp;
    pp.takeIntoAccountSensorPoseOnRobot = true;
    pp.robotPoseInTheWorld = robot;
    scan->unprojectInto(pts, pp);
    ASSERT_EQ(pts.size(), size_t(fixtures::kW * fixtures::kH));

    PanopticFrame f;
    depthFrameFrom(*scan, f);
    const Pose T = cameraPoseInWorld(robot, scan->sensorPose);
    for (size_t i = 0; i < pts.size(); ++i)
    {
        const int c = scan->points3D_idxs_x[i], r = scan->points3D_idxs_y[i];
        const Eigen::Vector3d ours = T * f.K.unproject(c, r, f.depth.at(r, c));
        float x, y, z;
        pts.getPoint(i, x, y, z);
        EXPECT_NEAR(ours.x(), x, 1e-4);
        EXPECT_NEAR(ours.y(), y, 1e-4);
        EXPECT_NEAR(ours.z(), z, 1e-4);
    }
    // And back: the MRPT sensor pose of the optical pose is the original.
    const mrpt::poses::CPose3D back = mrptSensorPoseOf(T);
    EXPECT_NEAR((back.asVectorVal() - (robot + scan->sensorPose).asVectorVal()).norm(), 0.0, 1e-9);
}

namespace
{
/// Inserts the wall + labels in the given order and returns the map.
PanopticNDTMap mapFromOrder(const std::vector<mrpt::obs::CObservation::Ptr>& obs)
{
    PanopticNDTMap m;
    const mrpt::poses::CPose3D robot;
    for (const auto& o : obs) EXPECT_TRUE(m.insertObservation(*o, robot));
    return m;
}
}  // namespace

TEST(PluginPairing, LabelsBeforeOrAfterTheirDepthGiveTheSameMap)
{
    using namespace fixtures;
    const auto after = mapFromOrder({wallScan(0), semanticImage(0), instanceImage(0)});
    const auto before = mapFromOrder({instanceImage(0), semanticImage(0), wallScan(0)});
    EXPECT_EQ(after.insertionStats().frames_with_labels, 1u);
    EXPECT_EQ(before.insertionStats().frames_with_labels, 1u);
    EXPECT_EQ(after.insertionStats().frames_geometry_only, 0u);
    EXPECT_FALSE(after.hasPending());
    ASSERT_EQ(after.core().voxels().size(), before.core().voxels().size());
    EXPECT_EQ(0, std::memcmp(after.core().voxels().voxels().data(), before.core().voxels().voxels().data(),
                             sizeof(Voxel) * after.core().voxels().size()));
    ASSERT_EQ(after.core().surfaceRecords().size(), before.core().surfaceRecords().size());
    EXPECT_EQ(0, std::memcmp(after.core().surfaceRecords().data(), before.core().surfaceRecords().data(),
                             sizeof(SurfaceRecord) * after.core().surfaceRecords().size()));
    // The left half is a chair instance: one new map instance.
    EXPECT_EQ(after.insertionStats().totals.new_instances, 1u);
    EXPECT_GT(after.insertionStats().totals.semantic_updates, 0u);
}

TEST(PluginPairing, DepthWithoutLabelsIsMappedGeometryOnlyAndCounted)
{
    using namespace fixtures;
    PanopticNDTMap m;
    const mrpt::poses::CPose3D robot;
    m.insertObservation(*wallScan(0), robot);
    m.insertObservation(*semanticImage(0.5), robot);  // far outside the tolerance
    m.insertObservation(*instanceImage(0.5), robot);
    EXPECT_TRUE(m.hasPending());
    m.insertObservation(*wallScan(1.0), robot);       // flushes frame 0 without labels
    m.flushPending();
    EXPECT_EQ(m.insertionStats().frames_geometry_only, 2u);
    EXPECT_EQ(m.insertionStats().frames_with_labels, 0u);
    EXPECT_EQ(m.insertionStats().totals.semantic_updates, 0u);
    EXPECT_FALSE(m.isEmpty());
}

TEST(PluginBadInput, LabelSizeMismatchNamesSensorAndTimestamp)
{
    using namespace fixtures;
    PanopticNDTMap m;
    const mrpt::poses::CPose3D robot;
    m.insertObservation(*wallScan(3), robot);
    m.insertObservation(*semanticImage(3, 16, 12), robot);
    try
    {
        m.insertObservation(*instanceImage(3), robot);
        FAIL() << "expected InputError";
    }
    catch (const InputError& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("RGBD_PANOPTIC_SEMANTIC"), std::string::npos) << msg;
        EXPECT_NE(msg.find("1700000003.000000"), std::string::npos) << msg;
        EXPECT_NE(msg.find("16x12"), std::string::npos) << msg;
    }
}

TEST(PluginBadInput, ClassOutsideTheClassSetNamesTheObservation)
{
    using namespace fixtures;
    PanopticNDTMap m;
    const mrpt::poses::CPose3D robot;
    m.insertObservation(*wallScan(4), robot);
    m.insertObservation(*labelImage(4, "_PANOPTIC_SEMANTIC", 77.9f, 1.9f), robot);
    try
    {
        m.insertObservation(*instanceImage(4), robot);
        FAIL() << "expected InputError";
    }
    catch (const InputError& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("class id 77"), std::string::npos) << msg;
        EXPECT_NE(msg.find("'RGBD' @ 1700000004"), std::string::npos) << msg;
    }
}

TEST(PluginBadInput, NonFloatLabelImageIsRejected)
{
    using namespace fixtures;
    auto img = semanticImage(5);
    img->image.resize(kW, kH, mrpt::img::CH_GRAY, mrpt::img::PixelDepth::D8U);
    PanopticNDTMap m;
    EXPECT_THROW(m.insertObservation(*img, mrpt::poses::CPose3D()), InputError);
}

TEST(PluginBadInput, DepthOutsideTheUsableRangeIsCounted)
{
    using namespace fixtures;
    auto scan = wallScan(6);
    scan->rangeImage(0, 0) = 0;       // no return
    scan->rangeImage(0, 1) = 12000;   // 12 m > max_range 10 m
    PanopticNDTMap m;
    m.insertObservation(*scan, mrpt::poses::CPose3D());
    m.flushPending();
    EXPECT_EQ(m.insertionStats().totals.skipped_invalid_depth, 1u);
    EXPECT_EQ(m.insertionStats().totals.skipped_over_range, 1u);
}

TEST(PluginView, VisualizationAndText)
{
    using namespace fixtures;
    // A near wall: several depth samples per voxel, so voxels have Gaussians.
    auto m = mapFromOrder({wallScan(0, 0.6f), semanticImage(0), instanceImage(0)});
    mrpt::opengl::CSetOfObjects scene;
    m.getVisualizationInto(scene);
    EXPECT_GT(scene.size(), 0u);
    m.renderOptions.shape = VoxelShape::Ellipsoids;
    mrpt::opengl::CSetOfObjects ell;
    m.getVisualizationInto(ell);
    EXPECT_GT(ell.size(), scene.size());  // one object per Gaussian
    const std::string s = m.asString();
    EXPECT_NE(s.find("PanopticNDTMap: voxel 0.100 m"), std::string::npos) << s;
}

// A range scan's uint16 image read in place (frameViewOf) maps exactly like the
// float copy depthFrameFrom makes, for depth and for Euclidean-range images.
TEST(PluginFrameView, ARangeScanViewMapsLikeItsFloatCopy)
{
    for (const bool range_is_depth : {true, false})
    {
        auto scan = fixtures::wallScan(0.0, 2.0f);
        for (int r = 0; r < fixtures::kH; ++r)
            for (int c = 0; c < fixtures::kW; ++c) scan->rangeImage(r, c) = uint16_t(1500 + 10 * r + 3 * c);
        scan->rangeImage(2, 3) = 0;  // invalid stays invalid
        scan->range_is_depth = range_is_depth;
        PanopticFrame copy;
        depthFrameFrom(*scan, copy);
        std::string source;
        const FrameView view = frameViewOf(*scan, source);
        EXPECT_EQ(source, describeObservation(*scan));
        EXPECT_EQ(view.depth.data, static_cast<const void*>(&scan->rangeImage(0, 0)));  // no copy
        EXPECT_EQ(view.depth.measures, range_is_depth ? RangeKind::Z : RangeKind::Ray);
        PanopticNDTMap a, b;
        const Pose T = cameraPoseInWorld(mrpt::poses::CPose3D(), scan->sensorPose);
        const FrameStats sa = a.integrate(copy, T), sb = b.integrate(view, T);
        EXPECT_EQ(sa.valid_pixels, uint64_t(fixtures::kW * fixtures::kH - 1));
        EXPECT_EQ(sa.valid_pixels, sb.valid_pixels);
        EXPECT_EQ(a.core().voxels().packedKeys(), b.core().voxels().packedKeys());
        EXPECT_EQ(0, std::memcmp(a.core().surfaceRecords().data(), b.core().surfaceRecords().data(),
                                 sizeof(SurfaceRecord) * a.core().surfaceRecords().size()));
    }
}
