// Writers of the published formats: label text, ScanNet instance files, RGB8 PNGs,
// Markdown tables and bar charts; atomic writes with errors naming the file.
#include <gtest/gtest.h>
#include <pndt/io/atomic_file.h>
#include <pndt/eval/bar_chart.h>
#include <pndt/eval/class_table.h>
#include <pndt/eval/label_png.h>
#include <pndt/eval/label_text.h>
#include <pndt/eval/markdown_table.h>
#include <pndt/eval/panoptic_codec.h>
#include <pndt/eval/scannet_instances.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "file_size_limit.h"

#include <cerrno>
#include <cstring>

using namespace pndt::eval;
namespace io = pndt::io;
namespace fs = std::filesystem;

namespace
{
class TempDir
{
   public:
    TempDir()
    {
        static std::atomic<int> counter{0};
        path_ = fs::temp_directory_path() /
                ("pndt_eval_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::create_directories(path_);
    }
    ~TempDir()
    {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    const fs::path& path() const { return path_; }

   private:
    fs::path path_;
};

std::string slurp(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

size_t filesIn(const fs::path& dir)
{
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.is_regular_file();
    return n;
}

template <typename F>
std::string errorOf(F&& f)
{
    try
    {
        f();
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return {};
}
}  // namespace

TEST(Writers, AtomicWriteLeavesNoTemporaryAndNamesTheFileOnError)
{
    TempDir d;
    io::writeFileAtomically(d.file("a.txt"), "first");
    io::writeFileAtomically(d.file("a.txt"), "second");  // replaces
    EXPECT_EQ(slurp(d.file("a.txt")), "second");
    EXPECT_EQ(filesIn(d.path()), 1u);
    const std::string missing = d.file("no_such_dir/b.txt");
    const std::string msg = errorOf([&] { io::writeFileAtomically(missing, "x"); });
    EXPECT_NE(msg.find(missing), std::string::npos) << msg;
    EXPECT_THROW(io::writeFileAtomically(missing, "x"), io::WriteError);
}

TEST(Writers, AStreamThatMeetsAFullDiskIsAWriteErrorWithTheReason)
{
    // A file size limit fails writes with EFBIG as a full disk fails them with
    // ENOSPC (SIGXFSZ ignored). 300 bytes stay in the stream's buffer until the
    // close writes them; 20000 fail while writing. Either way: an error naming the
    // file and the reason, and neither the file nor a temporary left (a stream
    // closed by its destructor dropped the close's error, and the short file was
    // renamed into place).
    TempDir d;
    std::string at_close, while_writing;
    const auto write = [&](const std::string& path, size_t bytes) {
        return errorOf([&] {
            io::writeFileAtomically(path, [&](const std::string& tmp) {
                std::ofstream f(tmp);
                f << std::string(bytes, 'x');
                io::closeWrittenStream(f, path);
            });
        });
    };
    {
        const pndt::test_support::FileSizeLimit full(100);
        at_close = write(d.file("small.txt"), 300);
        while_writing = write(d.file("big.txt"), 20000);
    }
    for (const auto& [msg, name] : {std::pair{at_close, "small.txt"}, std::pair{while_writing, "big.txt"}})
    {
        EXPECT_NE(msg.find(d.file(name)), std::string::npos) << msg;
        EXPECT_NE(msg.find(std::strerror(EFBIG)), std::string::npos) << msg;
    }
    EXPECT_EQ(filesIn(d.path()), 0u);
}

TEST(Writers, LabelText)
{
    TempDir d;
    writeSemanticText(d.file("sem.txt"), {0, 5, 40});
    EXPECT_EQ(slurp(d.file("sem.txt")), "0\n5\n40\n");
    const std::vector<uint32_t> pan = {0, encodePanoptic(5, 3), encodePanoptic(40, 65535)};
    writePanopticText(d.file("pan.txt"), pan);
    EXPECT_EQ(slurp(d.file("pan.txt")), "0\n327683\n2686975\n");
    EXPECT_EQ(readLabelText(d.file("pan.txt")), pan);
    io::writeFileAtomically(d.file("bad.txt"), "1\n-2\n");
    const std::string msg = errorOf([&] { readLabelText(d.file("bad.txt")); });
    EXPECT_NE(msg.find("bad.txt', line 2"), std::string::npos) << msg;
}

TEST(Writers, ScanNetInstances3D)
{
    TempDir d;
    const std::vector<InstancePrediction> p = {{5, 0.75, {0, 2}}, {39, 1.0, {3}}};
    const std::string main = writeScanNetInstances3D(d.path().string(), "scene0000_00", p, 4);
    EXPECT_EQ(main, d.file("scene0000_00.txt"));
    EXPECT_EQ(slurp(main), "predicted_masks/scene0000_00_000.txt 5 0.750000\n"
                           "predicted_masks/scene0000_00_001.txt 39 1.000000\n");
    EXPECT_EQ(slurp(d.file("predicted_masks/scene0000_00_000.txt")), "1\n0\n1\n0\n");
    EXPECT_EQ(slurp(d.file("predicted_masks/scene0000_00_001.txt")), "0\n0\n0\n1\n");
    const std::string msg =
        errorOf([&] { writeScanNetInstances3D(d.path().string(), "s", {{5, 1.0, {4}}}, 4); });
    EXPECT_NE(msg.find("s_000.txt"), std::string::npos) << msg;
}

TEST(Writers, ScanNetInstances2D)
{
    TempDir d;
    writeScanNetInstances2D(d.path().string(), "scene0000_00_000100", {{5, 0.5, {1, 4}}}, 3, 2);
    EXPECT_EQ(slurp(d.file("scene0000_00_000100.txt")), "predicted_masks/scene0000_00_000100_000.png 5 0.500000\n");
    const cv::Mat m = cv::imread(d.file("predicted_masks/scene0000_00_000100_000.png"), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(m.type(), CV_8UC1);
    EXPECT_EQ(m.at<uint8_t>(0, 1), 255);
    EXPECT_EQ(m.at<uint8_t>(1, 1), 255);  // index 4 = row 1, col 1
    EXPECT_EQ(m.at<uint8_t>(0, 0), 0);
    EXPECT_EQ(cv::countNonZero(m), 2);
}

TEST(Writers, PanopticPngIsRgbWithClassInRed)
{
    TempDir d;
    pndt::Image<uint16_t> sem(2, 1);
    pndt::Image<uint32_t> ins(2, 1);
    sem.at(0, 0) = 5;
    ins.at(0, 0) = 0x0102;  // G = 1, B = 2
    sem.at(0, 1) = 255;
    ins.at(0, 1) = 65535;
    writePanopticPng(d.file("p.png"), sem, ins);
    const cv::Mat bgr = cv::imread(d.file("p.png"), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(bgr.type(), CV_8UC3);
    EXPECT_EQ(bgr.at<cv::Vec3b>(0, 0), cv::Vec3b(2, 1, 5));  // OpenCV order B, G, R
    EXPECT_EQ(bgr.at<cv::Vec3b>(0, 1), cv::Vec3b(255, 255, 255));
    pndt::Image<uint16_t> sem2;
    pndt::Image<uint32_t> ins2;
    readPanopticPng(d.file("p.png"), sem2, ins2);
    EXPECT_EQ(sem2.data, sem.data);
    EXPECT_EQ(ins2.data, ins.data);
    sem.at(0, 0) = 256;
    const std::string msg = errorOf([&] { writePanopticPng(d.file("q.png"), sem, ins); });
    EXPECT_NE(msg.find("q.png"), std::string::npos) << msg;
    EXPECT_NE(msg.find("class 256"), std::string::npos) << msg;
    EXPECT_FALSE(fs::exists(d.file("q.png")));

    pndt::Image<uint16_t> s(3, 1);
    s.data = {0, 7, 40};
    writeSemanticPng(d.file("s.png"), s);
    pndt::Image<uint16_t> s2;
    readSemanticPng(d.file("s.png"), s2);
    EXPECT_EQ(s2.data, s.data);
    EXPECT_THROW(readSemanticPng(d.file("none.png"), s2), pndt::InputError);
}

namespace
{
ClassTable tinyTable()
{
    ClassTable t;
    t.title = "ScanNet valid";
    t.columns = {"IoU", "PQ"};
    t.rows = {{1, "wall", false, {0.5, 0.25}}, {5, "chair", true, {1.0, NAN}}};
    t.summary = {{0, "mean", false, {0.75, 0.25}}};
    return t;
}
}  // namespace

TEST(Writers, Markdown)
{
    const std::string md = toMarkdown(tinyTable());
    EXPECT_EQ(md,
              "### ScanNet valid\n\n"
              "| id | class | type | IoU | PQ |\n"
              "|---:|:---|:---|---:|---:|\n"
              "| 1 | wall | stuff | 50.00 | 25.00 |\n"
              "| 5 | chair | thing | 100.00 | - |\n"
              "| | **mean** | | 75.00 | 25.00 |\n");
    TempDir d;
    writeMarkdown(d.file("t.md"), tinyTable());
    EXPECT_EQ(slurp(d.file("t.md")), md);
}

TEST(Writers, CompareColumn)
{
    ClassTable b = tinyTable();
    b.rows[0].values = {0.1, 0.2};
    const ClassTable c = compareColumn({{"NDT", tinyTable()}, {"w/o NDT", b}}, "PQ", "PQ");
    EXPECT_EQ(c.columns, (std::vector<std::string>{"NDT", "w/o NDT"}));
    EXPECT_DOUBLE_EQ(c.value(1, "NDT"), 0.25);
    EXPECT_DOUBLE_EQ(c.value(1, "w/o NDT"), 0.2);
    EXPECT_DOUBLE_EQ(c.summary[0].values[1], 0.25);
    EXPECT_THROW(compareColumn({{"x", tinyTable()}}, "AP50"), std::invalid_argument);
}

TEST(Writers, BarChartPng)
{
    TempDir d;
    BarChartOptions o;
    o.columns = {"IoU"};
    writeBarChartPng(d.file("chart.png"), tinyTable(), o);
    const cv::Mat img = cv::imread(d.file("chart.png"), cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    EXPECT_GT(img.cols, 100);
    EXPECT_GT(img.rows, 320);
    // Series 0 colour (BGR 180, 119, 31) covers the bars: wall 50 %, chair 100 %, mean 75 %
    // of a 320 px axis, 11 px wide -> 11 * (160 + 320 + 240) pixels, plus the 12 x 12 legend box.
    cv::Mat mask;
    cv::inRange(img, cv::Scalar(180, 119, 31), cv::Scalar(180, 119, 31), mask);
    EXPECT_EQ(cv::countNonZero(mask), 11 * (160 + 320 + 240) + 12 * 12);
    BarChartOptions bad;
    bad.columns = {"nope"};
    EXPECT_THROW(renderBarChartPng(tinyTable(), bad), std::invalid_argument);
    // Several series, NaN skipped.
    EXPECT_FALSE(renderBarChartPng(tinyTable()).empty());
}
