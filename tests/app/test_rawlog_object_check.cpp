// Issue #23: every rawlog object's sizes are checked before MRPT allocates them. A rawlog
// written by our writer (RawlogFrameWriter) with one field patched at its offset: a depth
// image claiming 2^31 rows, a claim within the limits that the file does not back, a string
// length of 4 GiB: each stops with a message naming the file, the object and the field,
// read in a child process whose address space allows only 256 MiB more than it has (MRPT
// used to allocate what the file claims, and write through the null pointer it got back).
// Valid rawlogs (ours, MRPT-written with JPEG colour, the actions / sensory-frame format)
// read exactly as MRPT reads them.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/app/observation_stream.h>
#include <pndt/mrpt/rawlog_frames.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "rawlog_bytes.h"

namespace fs = std::filesystem;

namespace
{
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;  // their shadow memory needs an unlimited address space
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

struct Dir
{
    fs::path path;
    explicit Dir(const std::string& name)
        : path(fs::temp_directory_path() / (name + "_" + std::to_string(::getpid())))
    {
        fs::create_directories(path);
    }
    ~Dir() { fs::remove_all(path); }
};

/// Three frames of 40 x 30 pixels with labels and colour, written by our writer.
void writeFrames(const fs::path& path)
{
    pndt::RawlogFrameWriter w(path.string());
    for (int k = 0; k < 3; ++k)
    {
        pndt::PanopticFrame f;
        f.K = {40, 30, 30.0, 30.0, 19.5, 14.5};
        f.depth.resize(40, 30);
        f.semantic.resize(40, 30);
        f.semantic_score.resize(40, 30);
        f.instance.resize(40, 30);
        f.panoptic_score.resize(40, 30);
        pndt::Image<std::array<uint8_t, 3>> rgb;
        rgb.resize(40, 30);
        for (size_t i = 0; i < f.depth.data.size(); ++i)
        {
            f.depth.data[i] = 1.0f + 0.001f * float(i % 500);
            f.semantic.data[i] = uint16_t(i % 41);
            f.semantic_score.data[i] = 0.5f;
            f.instance.data[i] = uint32_t(i % 3);
            f.panoptic_score.data[i] = 0.25f;
            rgb.data[i] = {uint8_t(i), uint8_t(k), uint8_t(i / 3)};
        }
        w.write(f, 100.0 + k, pndt::Pose::Identity(), &rgb);
    }
    w.commit();
}

/// Reads `path` with ObservationStream in a child process whose address space may grow by
/// `extra_mb` only (not under ASan / TSan); returns the stop reason, or how the child died.
std::string readInChildUnderLimit(const fs::path& path, size_t extra_mb = 256,
                                  pndt::app::UncheckedObjects unchecked = pndt::app::UncheckedObjects::Refused)
{
    int fds[2];
    if (::pipe(fds) != 0) return "pipe failed";
    const pid_t pid = ::fork();
    if (pid == 0)
    {
        ::close(fds[0]);
        if (!kSanitized)
        {
            long pages = 0;
            std::ifstream("/proc/self/statm") >> pages;
            rlimit limit{};
            limit.rlim_cur = limit.rlim_max = rlim_t(pages) * rlim_t(::sysconf(_SC_PAGESIZE)) + (rlim_t(extra_mb) << 20);
            ::setrlimit(RLIMIT_AS, &limit);
        }
        std::string reason;
        try
        {
            pndt::app::ObservationStream in(path.string(), unchecked);
            size_t n = 0;
            while (in.next()) ++n;
            reason = in.truncated() ? in.stopReason() : "read " + std::to_string(n) + " observations";
        }
        catch (const std::exception& e)
        {
            reason = std::string("exception: ") + e.what();
        }
        [[maybe_unused]] const auto w = ::write(fds[1], reason.data(), reason.size());
        ::_exit(0);
    }
    ::close(fds[1]);
    std::string out;
    char buf[1024];
    for (ssize_t got; (got = ::read(fds[0], buf, sizeof(buf))) > 0;) out.append(buf, size_t(got));
    ::close(fds[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (WIFSIGNALED(status)) return "child killed by signal " + std::to_string(WTERMSIG(status));
    return out;
}

/// A scan with an 8 x 10 range image of 900 units (its rows, cols: "\x08\0\0\0\x0a\0\0\0").
mrpt::obs::CObservation3DRangeScan::Ptr smallScan()
{
    auto scan = mrpt::obs::CObservation3DRangeScan::Create();
    scan->hasRangeImage = true;
    scan->rangeImage_setSize(8, 10);
    scan->rangeImage.fill(900);
    return scan;
}
/// A rawlog of one smallScan() whose range image MRPT stores in `file` (under `base_dir`).
void writeExternalRangeScan(const fs::path& rawlog, const std::string& file, const std::string& base_dir)
{
    mrpt::io::CFileGZOutputStream out(rawlog.string());
    auto ar = mrpt::serialization::archiveFrom(out);
    auto scan = smallScan();
    scan->rangeImage_convertToExternalStorage(file, base_dir);
    ar << *scan;
}

/// Every object of the file as MRPT's own reader returns it (sensory frames flattened,
/// actions dropped), each serialised again, and the same for ObservationStream.
std::vector<std::string> serialised(const std::vector<mrpt::serialization::CSerializable::Ptr>& objects)
{
    std::vector<std::string> out;
    for (const auto& o : objects)
    {
        mrpt::io::CMemoryStream m;
        auto ar = mrpt::serialization::archiveFrom(m);
        ar << *o;
        out.emplace_back(static_cast<const char*>(m.getRawBufferData()), size_t(m.getTotalBytesCount()));
    }
    return out;
}
std::vector<std::string> readByMrpt(const fs::path& path)
{
    mrpt::io::CFileGZInputStream in(path.string());
    auto ar = mrpt::serialization::archiveFrom(in);
    std::vector<mrpt::serialization::CSerializable::Ptr> objects;
    try
    {
        for (;;)
        {
            mrpt::serialization::CSerializable::Ptr o;
            ar >> o;
            if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(o))
                for (const auto& x : *sf) objects.push_back(x);
            else if (std::dynamic_pointer_cast<mrpt::obs::CObservation>(o))
                objects.push_back(o);
        }
    }
    catch (const mrpt::serialization::CExceptionEOF&)
    {
    }
    return serialised(objects);
}
std::vector<std::string> readByStream(const fs::path& path, std::string& reason, size_t* unchecked = nullptr)
{
    pndt::app::ObservationStream in(path.string());
    std::vector<mrpt::serialization::CSerializable::Ptr> objects;
    while (auto o = in.next()) objects.push_back(o);
    reason = in.stopReason();
    if (unchecked) *unchecked = in.uncheckedObjectsRead();
    return serialised(objects);
}
}  // namespace

TEST(RawlogObjectCheck, ValidRawlogsReadExactlyAsMrptReadsThem)
{
    Dir dir("pndt_rawlog_check_valid");
    // Ours: robot pose, scan with raw colour, two float label images per frame.
    writeFrames(dir.path / "ours.rawlog");
    // MRPT-written: JPEG colour, a confidence image, points, pixel labels, a range layer.
    const bool was_disabled = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(false);
    {
        mrpt::io::CFileGZOutputStream out((dir.path / "mrpt.rawlog").string());
        auto ar = mrpt::serialization::archiveFrom(out);
        for (int k = 0; k < 2; ++k)
        {
            mrpt::obs::CObservation3DRangeScan scan;
            scan.timestamp = mrpt::Clock::fromDouble(10.0 + k);
            scan.sensorLabel = "KINECT";
            scan.hasRangeImage = true;
            scan.rangeImage_setSize(24, 32);
            scan.rangeImage.fill(uint16_t(1200 + k));
            scan.cameraParams.ncols = scan.cameraParamsIntensity.ncols = 32;
            scan.cameraParams.nrows = scan.cameraParamsIntensity.nrows = 24;
            scan.cameraParams.cameraName = "depth camera";
            scan.hasIntensityImage = true;
            scan.intensityImage.resize(32, 24, mrpt::img::CH_RGB);
            for (int r = 0; r < 24; ++r)
                for (int c = 0; c < 32; ++c) scan.intensityImage.setPixel(c, r, size_t((r * 9) << 16 | (c * 7) << 8 | k));
            scan.hasConfidenceImage = true;
            scan.confidenceImage.resize(32, 24, mrpt::img::CH_GRAY);
            for (int r = 0; r < 24; ++r)
                for (int c = 0; c < 32; ++c) scan.confidenceImage.setPixel(c, r, size_t(r + c));
            scan.hasPoints3D = true;
            scan.resizePoints3DVectors(5);
            for (int i = 0; i < 5; ++i) scan.points3D_x[size_t(i)] = float(i);
            auto labels = std::make_shared<mrpt::obs::TPixelLabelInfo<2>>();
            labels->setSize(24, 32);
            labels->setLabelName(3, "chair");
            labels->setLabel(2, 5, 3);
            scan.pixelLabels = labels;
            scan.rangeImageOtherLayers["LAST"].resize(24, 32);
            scan.rangeImageOtherLayers["LAST"].fill(7);
            ar << scan;
            mrpt::obs::CObservationImage image;
            image.sensorLabel = "CAMERA";
            image.timestamp = scan.timestamp;
            image.image = scan.intensityImage;
            ar << image;
        }
    }
    // The actions / sensory-frame format: odometry action, then a frame of observations.
    {
        mrpt::io::CFileGZOutputStream out((dir.path / "sf.rawlog").string());
        auto ar = mrpt::serialization::archiveFrom(out);
        for (int k = 0; k < 2; ++k)
        {
            mrpt::obs::CActionCollection actions;
            mrpt::obs::CActionRobotMovement2D move;
            move.computeFromOdometry(mrpt::poses::CPose2D(0.1 * k, 0, 0.05),
                                     mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
            actions.insert(move);
            ar << actions;
            mrpt::obs::CSensoryFrame sf;
            auto odo = mrpt::obs::CObservationOdometry::Create();
            odo->odometry = mrpt::poses::CPose2D(k, 0, 0);
            odo->hasVelocities = true;
            sf.insert(odo);
            auto pose = mrpt::obs::CObservationRobotPose::Create();
            pose->sensorLabel = "GT_POSE";
            sf.insert(pose);
            sf.insert(smallScan());
            ar << sf;
        }
    }
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(was_disabled);

    for (const char* name : {"ours.rawlog", "mrpt.rawlog", "sf.rawlog"})
    {
        std::string reason;
        const auto ours = readByStream(dir.path / name, reason), mrpts = readByMrpt(dir.path / name);
        EXPECT_EQ(reason, "") << name;
        EXPECT_GE(ours.size(), 4u) << name;
        EXPECT_TRUE(ours == mrpts) << name << ": " << ours.size() << " vs " << mrpts.size() << " objects";
    }
}

// Older versions, made from a file of our writer by removing the fields a version added:
// the robot pose at version 0 (no sensor pose), the scan at version 9 (no range layers), its
// two cameras at version 5 (no distortion model). They read as MRPT reads them.
TEST(RawlogObjectCheck, OlderVersionsReadAsMrptReadsThem)
{
    Dir dir("pndt_rawlog_check_old");
    writeFrames(dir.path / "ours.rawlog");
    std::string plain = readDecompressed(dir.path / "ours.rawlog");
    const std::string kScan = "mrpt::obs::CObservation3DRangeScan", kImage = "mrpt::obs::CObservationImage",
                      kCamera = "mrpt::img::TCamera";
    // Object #1, the robot pose, ends with its sensor pose (CPose3D v3: header, 12 doubles,
    // end flag: 119 bytes) and its own end flag; the scan's header follows.
    const size_t scan = plain.find(kScan) - 1;
    ASSERT_EQ(uint8_t(plain[scan - 120]), 0x80u | 20u);
    ASSERT_EQ(plain.substr(scan - 119, 20), "mrpt::poses::CPose3D");
    const size_t pose_version = plain.find("mrpt::obs::CObservationRobotPose") + 32;
    ASSERT_EQ(plain[pose_version], '\x01');
    // The scan ends with its number of range layers (0) and its end flag.
    const size_t image = plain.find(kImage, scan) - 1;
    ASSERT_EQ(plain.substr(image - 2, 2), std::string("\x00\x88", 2));
    plain.erase(image - 2, 1);
    // Its two cameras: version byte, 13 doubles, nrows, ncols, name, distortion model, end flag.
    for (size_t at = plain.find(kCamera, scan); at < image; at = plain.find(kCamera, at + 1))
    {
        const size_t version = at + kCamera.size();
        ASSERT_EQ(plain[version], '\x06');
        plain[version] = '\x05';
        uint32_t name = 0;
        std::memcpy(&name, &plain[version + 1 + 13 * 8 + 8], 4);
        const size_t model = version + 1 + 13 * 8 + 8 + 4 + name;
        ASSERT_EQ(uint8_t(plain[model + 1]), 0x88u);
        plain.erase(model, 1);
    }
    plain[scan + 1 + kScan.size()] = '\x09';
    plain.erase(scan - 120, 119);
    plain[pose_version] = '\x00';
    writeCompressed(dir.path / "old.rawlog", plain);

    std::string reason;
    const auto ours = readByStream(dir.path / "old.rawlog", reason), mrpts = readByMrpt(dir.path / "old.rawlog");
    EXPECT_EQ(reason, "");
    EXPECT_EQ(ours.size(), 12u);
    EXPECT_TRUE(ours == mrpts) << ours.size() << " vs " << mrpts.size() << " objects";
}

TEST(RawlogObjectCheck, ADepthImageOf2To31RowsIsRefusedNamingTheFieldBeforeAllocating)
{
    Dir dir("pndt_rawlog_check_rows");
    writeFrames(dir.path / "ours.rawlog");
    const std::string plain = readDecompressed(dir.path / "ours.rawlog");
    // The first scan's range image: has-range-image flag, range units (float), rows 30, cols 40.
    const size_t scan = plain.find("CObservation3DRangeScan");
    const size_t rows = plain.find(std::string("\x1e\0\0\0\x28\0\0\0", 8), scan);
    ASSERT_NE(rows, std::string::npos);
    ASSERT_EQ(plain[rows - 5], '\x01');

    std::string bad = plain;
    putU32(bad, rows, 0x80000000u);
    writeCompressed(dir.path / "rows.rawlog", bad);
    const std::string reason = readInChildUnderLimit(dir.path / "rows.rawlog");
    EXPECT_NE(reason.find((dir.path / "rows.rawlog").string()), std::string::npos) << reason;
    EXPECT_NE(reason.find("at object #2"), std::string::npos) << reason;
    EXPECT_NE(reason.find("CObservation3DRangeScan v10: a depth image of 2147483648 x 40 pixels (rows x cols), more "
                          "than a reader accepts"),
              std::string::npos)
        << reason;

    // Columns too, and a size within the limits (7000 x 7000, 98 MB) that the file does not
    // back: read as its bytes arrive, never allocated at once (the limit is 256 MiB above
    // what the child has; 98 MB for MRPT's image plus the bytes read would not fit twice).
    bad = plain;
    putU32(bad, rows + 4, 0xFFFFFFFFu);
    writeCompressed(dir.path / "cols.rawlog", bad);
    EXPECT_NE(readInChildUnderLimit(dir.path / "cols.rawlog").find("a depth image of 30 x 4294967295 pixels"),
              std::string::npos);
    bad = plain;
    putU32(bad, rows, 7000);
    putU32(bad, rows + 4, 7000);
    writeCompressed(dir.path / "unbacked.rawlog", bad);
    const std::string unbacked = readInChildUnderLimit(dir.path / "unbacked.rawlog", 64);
    EXPECT_NE(unbacked.find("at object #2"), std::string::npos) << unbacked;
    EXPECT_NE(unbacked.find("the file ends"), std::string::npos) << unbacked;

    // The same file unpatched reads whole in the same child.
    EXPECT_EQ(readInChildUnderLimit(dir.path / "ours.rawlog"), "read 12 observations");
}

TEST(RawlogObjectCheck, AStringLengthOf4GiBIsRefusedNamingTheField)
{
    Dir dir("pndt_rawlog_check_string");
    writeFrames(dir.path / "ours.rawlog");
    const std::string plain = readDecompressed(dir.path / "ours.rawlog");
    // The robot pose's sensor label "GT_POSE" of the second frame (object #5).
    const size_t label = plain.find(std::string("\x07\0\0\0GT_POSE", 11), plain.find("GT_POSE") + 1);
    ASSERT_NE(label, std::string::npos);
    std::string bad = plain;
    putU32(bad, label, 0xFFFFFFF0u);
    writeCompressed(dir.path / "label.rawlog", bad);
    const std::string reason = readInChildUnderLimit(dir.path / "label.rawlog");
    EXPECT_NE(reason.find("at object #5"), std::string::npos) << reason;
    EXPECT_NE(reason.find("CObservationRobotPose v1: the sensor label claims a string of 4294967280 bytes"),
              std::string::npos)
        << reason;

    // A camera name inside the scan's TCamera (nested objects are named in turn).
    const size_t camera = plain.find("TCamera");
    ASSERT_NE(camera, std::string::npos);
    // TCamera v6: version byte, 13 doubles, nrows, ncols, then the name's length.
    const size_t name = camera + 7 + 1 + 13 * 8 + 8;
    bad = plain;
    putU32(bad, name, 0x7FFFFFFFu);
    writeCompressed(dir.path / "camera.rawlog", bad);
    const std::string nested = readInChildUnderLimit(dir.path / "camera.rawlog");
    EXPECT_NE(nested.find("CObservation3DRangeScan v10 > TCamera v6: a camera's name claims a string of 2147483647"),
              std::string::npos)
        << nested;
}

TEST(RawlogObjectCheck, StrictlyClassesAndVersionsItDoesNotCheckAreRefusedByName)
{
    Dir dir("pndt_rawlog_check_class");
    {
        mrpt::io::CFileGZOutputStream out((dir.path / "laser.rawlog").string());
        auto ar = mrpt::serialization::archiveFrom(out);
        mrpt::obs::CObservationRobotPose pose;
        ar << pose;
        mrpt::obs::CObservation2DRangeScan laser;
        laser.resizeScan(10);
        ar << laser;
    }
    const std::string reason = readInChildUnderLimit(dir.path / "laser.rawlog");  // strict
    EXPECT_NE(reason.find("at object #2"), std::string::npos) << reason;
    EXPECT_NE(reason.find("a 'mrpt::obs::CObservation2DRangeScan' object, which this reader does not accept"), std::string::npos)
        << reason;

    // A range image stored in a file of its own (MRPT's load() would size it from that
    // file, unchecked): refused strictly, naming it.
    writeExternalRangeScan(dir.path / "external.rawlog", "range.bin", dir.path.string() + "/");
    const std::string external = readInChildUnderLimit(dir.path / "external.rawlog");
    EXPECT_NE(external.find("at object #1"), std::string::npos) << external;
    EXPECT_NE(external.find("CObservation3DRangeScan v10: externally stored range images, which this reader does "
                            "not accept: MRPT's load() would size them from that file unchecked"),
              std::string::npos)
        << external;

    writeFrames(dir.path / "ours.rawlog");
    std::string plain = readDecompressed(dir.path / "ours.rawlog");
    const size_t scan = plain.find("CObservation3DRangeScan");
    plain[scan + 23] = char(11);  // the version byte after the class name
    writeCompressed(dir.path / "version.rawlog", plain);
    const std::string version = readInChildUnderLimit(dir.path / "version.rawlog");
    EXPECT_NE(version.find("CObservation3DRangeScan v11: version 11 is not one MRPT 2.5.8 reads (0..10)"),
              std::string::npos)
        << version;
}

// A robot's rawlog carries other sensors (a 2D laser, odometry, an IMU) beside the camera,
// often in sensory frames. By default MRPT's own reader reads the parts without a layout
// here (their bytes collected as it goes) and the walk goes on after them: such a rawlog
// reads exactly as MRPT reads it, the objects holding unchecked parts are counted, and the
// checked classes stay checked around them (a camera scan after a laser in a sensory frame).
TEST(RawlogObjectCheck, OtherSensorsObjectsAreReadByMrptByDefaultAndTheCameraStaysChecked)
{
    Dir dir("pndt_rawlog_check_other");
    mrpt::obs::CObservation2DRangeScan laser;
    laser.resizeScan(10);
    for (size_t i = 0; i < 10; ++i) laser.setScanRange(i, 1.0f + 0.1f * float(i));
    laser.sensorLabel = "LASER";
    mrpt::obs::CObservationRobotPose pose;
    pose.pose.mean = mrpt::poses::CPose3D(1, 2, 3, 0.1, 0.2, 0.3);
    {
        mrpt::io::CFileGZOutputStream out((dir.path / "robot.rawlog").string());
        auto ar = mrpt::serialization::archiveFrom(out);
        ar << pose << laser;          // observations-only format
        mrpt::obs::CSensoryFrame sf;  // a sensory frame: laser, camera scan, pose
        sf.insert(mrpt::obs::CObservation2DRangeScan::Create(laser));
        sf.insert(smallScan());
        sf.insert(mrpt::obs::CObservationRobotPose::Create(pose));
        ar << sf << pose;
    }
    std::string reason;
    size_t unchecked = 0;
    const auto ours = readByStream(dir.path / "robot.rawlog", reason, &unchecked);
    EXPECT_EQ(reason, "");
    EXPECT_EQ(unchecked, 2u);  // the laser, and the sensory frame holding one
    const auto mrpts = readByMrpt(dir.path / "robot.rawlog");
    ASSERT_EQ(ours.size(), 6u);
    EXPECT_EQ(ours, mrpts);
    EXPECT_EQ(readInChildUnderLimit(dir.path / "robot.rawlog", 256, pndt::app::UncheckedObjects::ReadByMrpt),
              "read 6 observations");

    // Strictly, the file stops at the laser (object #2).
    const std::string strict = readInChildUnderLimit(dir.path / "robot.rawlog");
    EXPECT_NE(strict.find("at object #2"), std::string::npos) << strict;
    EXPECT_NE(strict.find("CObservation2DRangeScan' object, which this reader does not accept"), std::string::npos)
        << strict;

    // The camera scan after the laser in the sensory frame claims 2^31 rows: still refused
    // by default, naming the field, before MRPT allocates it.
    std::string plain = readDecompressed(dir.path / "robot.rawlog");
    const size_t scan = plain.find("CObservation3DRangeScan");
    ASSERT_NE(scan, std::string::npos);
    const size_t rows = plain.find(std::string("\x08\0\0\0\x0a\0\0\0", 8), scan);
    ASSERT_NE(rows, std::string::npos);
    ASSERT_EQ(plain[rows - 5], '\x01');
    putU32(plain, rows, 0x80000000u);
    writeCompressed(dir.path / "rows.rawlog", plain);
    const std::string rows_reason =
        readInChildUnderLimit(dir.path / "rows.rawlog", 256, pndt::app::UncheckedObjects::ReadByMrpt);
    EXPECT_NE(rows_reason.find("at object #3"), std::string::npos) << rows_reason;
    EXPECT_NE(rows_reason.find("CSensoryFrame v2 > CObservation3DRangeScan v10: a depth image of 2147483648 x 10"),
              std::string::npos)
        << rows_reason;
}

// A scan whose range image lives in a file of its own: MRPT reads it by default (and its
// load() fetches the image), strictly it is refused naming it.
TEST(RawlogObjectCheck, ExternallyStoredRangeImagesAreReadByMrptByDefault)
{
    Dir dir("pndt_rawlog_check_external_default");
    writeExternalRangeScan(dir.path / "external.rawlog", (dir.path / "range.bin").string(), "");
    pndt::app::ObservationStream in((dir.path / "external.rawlog").string());
    auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(in.next());
    ASSERT_TRUE(obs) << in.stopReason();
    EXPECT_EQ(in.next(), nullptr);
    EXPECT_FALSE(in.truncated()) << in.stopReason();
    EXPECT_EQ(in.uncheckedObjectsRead(), 1u);
    obs->load();
    ASSERT_EQ(obs->rangeImage.rows(), 8);
    ASSERT_EQ(obs->rangeImage.cols(), 10);
    EXPECT_EQ(obs->rangeImage(3, 4), 900);
}
