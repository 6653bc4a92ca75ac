// ObservationStream on damaged rawlogs: wherever a file is cut, reading stops
// with a message naming the file and the object, never with libjpeg's exit().
// ReadAheadStream: the same observations and stop reason, read on a thread.
// RawlogSequence: several files read as one, in time order.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/app/observation_stream.h>
#include <pndt/app/rawlog_sequence.h>
#include <pndt/app/read_ahead_stream.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "rawlog_bytes.h"

namespace fs = std::filesystem;

namespace
{
/// Two frames (robot pose + scan with a JPEG-compressed colour image) at t0 and t0 + 1 s;
/// with `repeated_pose` >= 0 a robot pose stamped then comes first (as a recording cut into
/// files repeats at a file's start the poses an earlier file holds).
std::string writeColourRawlog(const fs::path& path, double t0 = 100.0, double repeated_pose = -1)
{
    // MRPT 2.5 stores colour images raw unless told otherwise (as pndt-convert does).
    const bool was_disabled = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(false);
    {
        mrpt::io::CFileGZOutputStream out(path.string());
        auto ar = mrpt::serialization::archiveFrom(out);
        if (repeated_pose >= 0)
        {
            mrpt::obs::CObservationRobotPose pose;
            pose.timestamp = mrpt::Clock::fromDouble(repeated_pose);
            ar << pose;
        }
        for (int k = 0; k < 2; ++k)
        {
            mrpt::obs::CObservationRobotPose pose;
            pose.timestamp = mrpt::Clock::fromDouble(t0 + k);
            ar << pose;
            mrpt::obs::CObservation3DRangeScan scan;
            scan.timestamp = pose.timestamp;
            scan.hasRangeImage = true;
            scan.rangeImage_setSize(48, 64);
            scan.cameraParams.ncols = scan.cameraParamsIntensity.ncols = 64;
            scan.cameraParams.nrows = scan.cameraParamsIntensity.nrows = 48;
            scan.rangeImage.fill(1000);
            scan.hasIntensityImage = true;
            scan.intensityImage.resize(64, 48, mrpt::img::CH_RGB);
            for (int r = 0; r < 48; ++r)
                for (int c = 0; c < 64; ++c) scan.intensityImage.setPixel(c, r, size_t((r * 5) << 16 | (c * 3) << 8 | k));
            ar << scan;
        }
    }
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(was_disabled);
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}
}  // namespace

TEST(ObservationStream, ACutAnywhereStopsWithAMessageNamingTheFile)
{
    const fs::path dir = fs::temp_directory_path() / ("pndt_obs_stream_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string bytes = writeColourRawlog(dir / "whole.rawlog");
    {
        pndt::app::ObservationStream whole((dir / "whole.rawlog").string());
        size_t n = 0;
        while (whole.next()) ++n;
        EXPECT_EQ(n, 4u);
        EXPECT_FALSE(whole.truncated());
    }
    // Cut every 16 bytes: inside headers, depth data and the JPEG bytes of the colour images.
    int cuts = 0, truncated = 0;
    for (size_t length = 16; length < bytes.size(); length += 16, ++cuts)
    {
        const fs::path cut = dir / "cut.rawlog";
        std::ofstream(cut, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(length));
        pndt::app::ObservationStream in(cut.string());
        size_t n = 0;
        while (in.next()) ++n;
        EXPECT_LE(n, 4u);
        if (in.truncated())
        {
            ++truncated;
            EXPECT_NE(in.stopReason().find(cut.string()), std::string::npos) << in.stopReason();
            EXPECT_NE(in.stopReason().find("truncated or corrupt at object #" + std::to_string(n + 1)),
                      std::string::npos)
                << in.stopReason();
        }
    }
    std::printf("[measured] %d cuts of a %zu-byte rawlog, %d reported as truncated\n", cuts, bytes.size(), truncated);
    EXPECT_GE(truncated, cuts * 9 / 10);  // a cut at the end of an object may end cleanly
    fs::remove_all(dir);
}

TEST(ObservationStream, ACorruptJpegColourImageStopsWithAMessageNotTheProcess)
{
    const fs::path dir = fs::temp_directory_path() / ("pndt_obs_jpeg_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    writeColourRawlog(dir / "whole.rawlog");
    const std::string plain = readDecompressed(dir / "whole.rawlog");
    // The second scan's JPEG (object #4): SOI, then APP0 with its 16-byte length.
    const size_t first = plain.find("\xFF\xD8\xFF\xE0");
    const size_t second = plain.find("\xFF\xD8\xFF\xE0", first + 1);
    ASSERT_NE(second, std::string::npos);
    ASSERT_EQ(plain.substr(second + 4, 2), std::string("\x00\x10", 2));

    const auto read = [&](const std::string& bytes, std::vector<double>& stamps) {
        writeCompressed(dir / "damaged.rawlog", bytes);
        pndt::app::ObservationStream in((dir / "damaged.rawlog").string());
        stamps.clear();
        while (auto o = in.next()) stamps.push_back(mrpt::Clock::toDouble(o->timestamp));
        return in.truncated() ? in.stopReason() : std::string();
    };
    std::vector<double> stamps;
    ASSERT_EQ(read(plain, stamps), "");  // the round trip through our writer is a valid file
    EXPECT_EQ(stamps.size(), 4u);

    // Bytes libjpeg cannot decode behind the SOI: "Quantization table 0x00 was
    // not defined", which its default error handler (MRPT's) answers with exit().
    std::string garbage = plain;
    for (size_t i = second + 2; i < second + 40; ++i) garbage[i] = char(0x5A);
    const std::string reason = read(garbage, stamps);
    EXPECT_EQ(stamps, (std::vector<double>{100.0, 100.0, 101.0}));
    EXPECT_NE(reason.find((dir / "damaged.rawlog").string()), std::string::npos) << reason;
    EXPECT_NE(reason.find("at object #4"), std::string::npos) << reason;
    EXPECT_NE(reason.find("JPEG bytes are corrupt"), std::string::npos) << reason;

    // A second SOF marker where the EOI should be: OpenCV decodes the image (the guard used to
    // pass it), but MRPT's jpeg_finish_decompress reads on to the EOI and libjpeg exit()s with
    // "Invalid JPEG file structure: two SOF markers" (found by fuzz_rawlog). The check makes
    // MRPT's calls itself (header, scanlines, finish) with an error handler that returns.
    uint32_t length = 0;
    std::memcpy(&length, &plain[second - 4], 4);
    ASSERT_EQ(plain.substr(second + length - 2, 2), "\xFF\xD9");
    std::string two_sof = plain;
    two_sof[second + length - 1] = '\xC0';
    const std::string sof_reason = read(two_sof, stamps);
    EXPECT_EQ(stamps, (std::vector<double>{100.0, 100.0, 101.0}));
    EXPECT_NE(sof_reason.find("at object #4"), std::string::npos) << sof_reason;
    EXPECT_NE(sof_reason.find("JPEG bytes are corrupt (libjpeg cannot decode them: Invalid JPEG file structure: "
                              "two SOF markers)"),
              std::string::npos)
        << sof_reason;

    // Damage libjpeg recovers from with a warning (an APP0 length of 1: it
    // skips to the next marker) is no reason to stop: MRPT decodes the image.
    std::string recoverable = plain;
    recoverable[second + 5] = '\x01';
    EXPECT_EQ(read(recoverable, stamps), "");
    EXPECT_EQ(stamps.size(), 4u);
    fs::remove_all(dir);
}

// Issue #23 (allocation limits): MRPT decodes a colour image at the size its JPEG header
// claims; a header claiming 30000 x 30000 pixels (2.7 GB decoded) is refused first.
TEST(ObservationStream, AJpegHeaderClaimingAHugeImageStopsBeforeDecoding)
{
    const fs::path dir = fs::temp_directory_path() / ("pndt_obs_hugejpeg_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    writeColourRawlog(dir / "whole.rawlog");
    std::string plain = readDecompressed(dir / "whole.rawlog");
    const size_t first = plain.find("\xFF\xD8\xFF\xE0");
    const size_t sof = plain.find("\xFF\xC0", first);
    ASSERT_NE(sof, std::string::npos);
    for (size_t i : {sof + 5, sof + 7})  // height, width (big-endian 16 bits) = 30000
    {
        plain[i] = '\x75';
        plain[i + 1] = '\x30';
    }
    writeCompressed(dir / "huge.rawlog", plain);
    pndt::app::ObservationStream in((dir / "huge.rawlog").string());
    size_t n = 0;
    while (in.next()) ++n;
    EXPECT_EQ(n, 1u);  // the robot pose before the first scan
    ASSERT_TRUE(in.truncated());
    EXPECT_NE(in.stopReason().find("JPEG header is implausible"), std::string::npos) << in.stopReason();
    EXPECT_NE(in.stopReason().find("30000 x 30000"), std::string::npos) << in.stopReason();
    fs::remove_all(dir);
}

TEST(ReadAheadStream, SameObservationsInOrderAndTheSameStopReason)
{
    const fs::path dir = fs::temp_directory_path() / ("pndt_read_ahead_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string bytes = writeColourRawlog(dir / "whole.rawlog");
    const auto stamps = [](auto& in) {
        std::vector<std::pair<std::string, double>> out;
        while (auto o = in.next()) out.emplace_back(o->GetRuntimeClass()->className, mrpt::Clock::toDouble(o->timestamp));
        return out;
    };
    pndt::app::ObservationStream plain((dir / "whole.rawlog").string());
    pndt::app::ReadAheadStream ahead((dir / "whole.rawlog").string(), 1);
    const auto a = stamps(plain), b = stamps(ahead);
    ASSERT_EQ(a.size(), 4u);
    EXPECT_EQ(a, b);
    EXPECT_FALSE(ahead.truncated());
    EXPECT_DOUBLE_EQ(ahead.progress(), 1.0);

    // A truncated file: the same observations before the cut, the same reason.
    const fs::path cut = dir / "cut.rawlog";
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() * 3 / 4));
    pndt::app::ObservationStream plain_cut(cut.string());
    pndt::app::ReadAheadStream ahead_cut(cut.string(), 2);
    EXPECT_EQ(stamps(plain_cut), stamps(ahead_cut));
    ASSERT_TRUE(plain_cut.truncated());
    EXPECT_TRUE(ahead_cut.truncated());
    EXPECT_EQ(ahead_cut.stopReason(), plain_cut.stopReason());

    // Dropped after one observation, with the reader waiting on a full queue: it stops.
    {
        pndt::app::ReadAheadStream early((dir / "whole.rawlog").string(), 1);
        EXPECT_TRUE(early.next());
    }
    EXPECT_THROW(pndt::app::ReadAheadStream((dir / "missing.rawlog").string()), std::runtime_error);
    fs::remove_all(dir);
}

// The progress a bar shows is that of the observations handed out, measured in
// bytes of the file on disk: not of what the reader has read ahead, and not the
// decompressed offset over the compressed size (which once reached 100 % with a
// third of the frames mapped).
TEST(ReadAheadStream, ProgressFollowsTheObservationsHandedOut)
{
    const fs::path dir = fs::temp_directory_path() / ("pndt_read_ahead_progress_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path path = dir / "noise.rawlog";
    constexpr int kScans = 40;
    {
        mrpt::io::CFileGZOutputStream out(path.string());
        auto ar = mrpt::serialization::archiveFrom(out);
        uint32_t state = 12345;  // incompressible ranges: every scan takes the same share of the file
        for (int k = 0; k < kScans; ++k)
        {
            mrpt::obs::CObservation3DRangeScan scan;
            scan.timestamp = mrpt::Clock::fromDouble(100.0 + k);
            scan.hasRangeImage = true;
            scan.rangeImage_setSize(160, 200);
            for (int r = 0; r < 160; ++r)
                for (int c = 0; c < 200; ++c)
                {
                    state = state * 1664525u + 1013904223u;
                    scan.rangeImage(r, c) = uint16_t(state >> 16);
                }
            ar << scan;
        }
    }
    pndt::app::ReadAheadStream in(path.string(), 16);
    double last = 0;
    for (int k = 1; k <= kScans; ++k)
    {
        ASSERT_TRUE(in.next());
        const double p = in.progress();
        EXPECT_GE(p, last);
        // zlib reads ahead by at most twice its 32 KiB buffer (of ~2.6 MB).
        EXPECT_NEAR(p, double(k) / kScans, 0.06) << "after " << k << " of " << kScans;
        last = p;
    }
    EXPECT_FALSE(in.next());
    EXPECT_DOUBLE_EQ(in.progress(), 1.0);
    fs::remove_all(dir);
}

namespace
{
/// Class name and stamp of every observation, in order.
template <class Stream>
std::vector<std::pair<std::string, double>> readAll(Stream& in)
{
    std::vector<std::pair<std::string, double>> out;
    while (auto o = in.next()) out.emplace_back(o->GetRuntimeClass()->className, mrpt::Clock::toDouble(o->timestamp));
    return out;
}
}  // namespace

// A recording cut into files (pndt-live --record-minutes) read as one: every file's
// observations in turn; poses a file repeats from the one before are skipped; progress
// counts all files' bytes; files out of time order, missing or damaged are named.
TEST(RawlogSequence, ReadsFilesInTurnSkipsRepeatedPosesAndNamesWhatIsWrong)
{
    const fs::path dir = fs::temp_directory_path() / ("pndt_rawlog_sequence_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string a = (dir / "rec-0000.rawlog").string(), b = (dir / "rec-0001.rawlog").string();
    const std::string first_bytes = writeColourRawlog(a, 100.0);
    writeColourRawlog(b, 102.0, 101.0);  // starts with the pose at 101 s that a already holds
    {
        pndt::app::RawlogSequence seq({a, b});
        std::vector<std::pair<std::string, double>> got;
        double last_progress = 0;
        while (auto o = seq.next())
        {
            got.emplace_back(o->GetRuntimeClass()->className, mrpt::Clock::toDouble(o->timestamp));
            EXPECT_GE(seq.progress(), last_progress);
            last_progress = seq.progress();
            if (got.size() == 4)
            {
                EXPECT_LT(seq.progress(), 0.75) << "one file of two read";
            }
        }
        const std::vector<std::pair<std::string, double>> expected = {
            {"mrpt::obs::CObservationRobotPose", 100.0}, {"mrpt::obs::CObservation3DRangeScan", 100.0},
            {"mrpt::obs::CObservationRobotPose", 101.0}, {"mrpt::obs::CObservation3DRangeScan", 101.0},
            {"mrpt::obs::CObservationRobotPose", 102.0}, {"mrpt::obs::CObservation3DRangeScan", 102.0},
            {"mrpt::obs::CObservationRobotPose", 103.0}, {"mrpt::obs::CObservation3DRangeScan", 103.0}};
        EXPECT_EQ(got, expected);
        EXPECT_FALSE(seq.truncated());
        EXPECT_DOUBLE_EQ(seq.progress(), 1.0);
        EXPECT_EQ(seq.path(), b);
    }
    // b on its own keeps its first pose (a replay of the newest files of a black box).
    {
        pndt::app::ObservationStream alone(b);
        ASSERT_EQ(readAll(alone).size(), 5u);
    }
    // The wrong order (or one file twice): refused at the second file's first scan, naming both.
    for (const auto& files : {std::vector<std::string>{b, a}, std::vector<std::string>{a, a}})
    {
        pndt::app::RawlogSequence seq(files);
        try
        {
            while (seq.next())
            {
            }
            ADD_FAILURE() << "files out of time order were read";
        }
        catch (const std::runtime_error& e)
        {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(files[1] + ": its first depth frame (t=1"), std::string::npos) << msg;
            EXPECT_NE(msg.find("is not later than the last one of " + files[0]), std::string::npos) << msg;
        }
    }
    // A missing file is named before anything is read.
    try
    {
        pndt::app::RawlogSequence seq({a, (dir / "rec-0002.rawlog").string()});
        ADD_FAILURE() << "a missing file was not named";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("rec-0002.rawlog: no such file"), std::string::npos) << e.what();
    }
    // A damaged file ends the sequence there: what it holds, then its reason; b is not read.
    const std::string cut = (dir / "cut.rawlog").string();
    std::ofstream(cut, std::ios::binary).write(first_bytes.data(), std::streamsize(first_bytes.size() * 3 / 4));
    pndt::app::ObservationStream cut_alone(cut);
    const auto before_cut = readAll(cut_alone);
    pndt::app::ReadAheadStream seq(std::vector<std::string>{cut, b}, 2);
    EXPECT_EQ(readAll(seq), before_cut);
    EXPECT_TRUE(seq.truncated());
    EXPECT_EQ(seq.stopReason(), cut_alone.stopReason());
    EXPECT_EQ(seq.stopReason().rfind(cut, 0), 0u) << seq.stopReason();
    fs::remove_all(dir);
}
