// Depth, colour and label image readers.
#include "io_test_util.h"

#include <pndt/io/images.h>

namespace pndt::io::test
{
using Images = TempDirTest;

TEST_F(Images, DepthPngMillimetresAndTumScale)
{
    cv::Mat m(2, 3, CV_16UC1);
    m.at<uint16_t>(0, 0) = 0;
    m.at<uint16_t>(0, 1) = 1000;
    m.at<uint16_t>(0, 2) = 1234;
    m.at<uint16_t>(1, 0) = 65535;
    m.at<uint16_t>(1, 1) = 5000;
    m.at<uint16_t>(1, 2) = 1;
    const std::string p = writePng16(path("d.png"), m);

    const Image<float> mm = readDepthImage(p);  // default: 1000 units per metre
    ASSERT_EQ(mm.width, 3);
    ASSERT_EQ(mm.height, 2);
    EXPECT_EQ(mm.at(0, 0), 0.0f);
    EXPECT_FLOAT_EQ(mm.at(0, 1), 1.0f);
    EXPECT_FLOAT_EQ(mm.at(0, 2), 1.234f);
    EXPECT_FLOAT_EQ(mm.at(1, 0), 65.535f);
    EXPECT_FLOAT_EQ(mm.at(1, 2), 0.001f);

    const Image<float> tum = readDepthImage(p, kDepthUnitsTum);
    EXPECT_FLOAT_EQ(tum.at(1, 1), 1.0f);
    EXPECT_FLOAT_EQ(tum.at(0, 1), 0.2f);
    EXPECT_EQ(tum.at(0, 0), 0.0f);
}

TEST_F(Images, DepthErrorsNameTheFile)
{
    cv::Mat m8(2, 2, CV_8UC1, cv::Scalar(7));
    cv::imwrite(path("eight.png"), m8);
    EXPECT_INPUT_ERROR(readDepthImage(path("eight.png")), "eight.png", "16-bit single-channel", "8-bit unsigned, 1 channel");
    cv::Mat m3(2, 2, CV_16UC3, cv::Scalar(1, 2, 3));
    cv::imwrite(path("rgb16.png"), m3);
    EXPECT_INPUT_ERROR(readDepthImage(path("rgb16.png")), "rgb16.png", "3 channels");
    EXPECT_INPUT_ERROR(readDepthImage(dir() + "/missing.png"), "missing.png", "file not found");
    EXPECT_INPUT_ERROR(readDepthImage(write("junk.png", "this is not a png")), "junk.png", "cannot decode");
    cv::Mat ok(1, 1, CV_16UC1, cv::Scalar(5));
    EXPECT_INPUT_ERROR(readDepthImage(writePng16(path("ok.png"), ok), 0.0), "ok.png", "units per metre");
}

TEST_F(Images, ColorIsReturnedAsRgb)
{
    cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(0, 0, 0));
    bgr.at<cv::Vec3b>(0, 1) = cv::Vec3b(10, 20, 30);  // B=10 G=20 R=30
    bgr.at<cv::Vec3b>(1, 0) = cv::Vec3b(255, 0, 0);   // pure blue
    cv::imwrite(path("c.png"), bgr);
    const RgbImage img = readColorImage(path("c.png"));
    ASSERT_EQ(img.width, 2);
    ASSERT_EQ(img.height, 2);
    EXPECT_EQ(img.at(0, 1), (std::array<uint8_t, 3>{30, 20, 10}));
    EXPECT_EQ(img.at(1, 0), (std::array<uint8_t, 3>{0, 0, 255}));

    cv::Mat bgra(1, 1, CV_8UC4, cv::Scalar(1, 2, 3, 4));
    cv::imwrite(path("a.png"), bgra);
    EXPECT_EQ(readColorImage(path("a.png")).at(0, 0), (std::array<uint8_t, 3>{3, 2, 1}));

    cv::Mat flat(8, 8, CV_8UC3, cv::Scalar(40, 120, 200));
    cv::imwrite(path("c.jpg"), flat);
    const RgbImage jpg = readColorImage(path("c.jpg"));
    ASSERT_EQ(jpg.width, 8);
    EXPECT_NEAR(jpg.at(4, 4)[0], 200, 3);
    EXPECT_NEAR(jpg.at(4, 4)[2], 40, 3);
}

TEST_F(Images, ColorErrors)
{
    cv::Mat gray(2, 2, CV_8UC1, cv::Scalar(1));
    cv::imwrite(path("g.png"), gray);
    EXPECT_INPUT_ERROR(readColorImage(path("g.png")), "g.png", "3 or 4 channels", "1 channel");
    cv::Mat c16(2, 2, CV_16UC3, cv::Scalar(1, 2, 3));
    cv::imwrite(path("c16.png"), c16);
    EXPECT_INPUT_ERROR(readColorImage(path("c16.png")), "c16.png", "16-bit");
    EXPECT_INPUT_ERROR(readColorImage(dir() + "/none.jpg"), "none.jpg", "file not found");
}

TEST_F(Images, LabelImages)
{
    cv::Mat s8(1, 2, CV_8UC1);
    s8.at<uint8_t>(0, 0) = 3;
    s8.at<uint8_t>(0, 1) = 40;
    cv::imwrite(path("s8.png"), s8);
    const auto a = readLabelImage(path("s8.png"));
    EXPECT_EQ(a.at(0, 0), 3);
    EXPECT_EQ(a.at(0, 1), 40);

    cv::Mat s16(1, 1, CV_16UC1, cv::Scalar(549));
    cv::imwrite(path("s16.png"), s16);
    EXPECT_EQ(readLabelImage(path("s16.png")).at(0, 0), 549);

    // Hypersim instance PNG: R = semantic class, (G << 8) | B = instance id. OpenCV order is BGR.
    cv::Mat inst(1, 1, CV_8UC3);
    inst.at<cv::Vec3b>(0, 0) = cv::Vec3b(/*B*/ 2, /*G*/ 1, /*R*/ 5);
    cv::imwrite(path("inst.png"), inst);
    EXPECT_EQ(readLabelImage(path("inst.png")).at(0, 0), (1 << 8) | 2);

    cv::Mat f(1, 1, CV_32FC1, cv::Scalar(1.5));
    cv::imwrite(path("f.pfm"), f);
    EXPECT_INPUT_ERROR(readLabelImage(path("f.pfm")), "f.pfm", "32-bit float");
}


// Allocation limits (issue #23): a header claiming a huge image is refused before
// OpenCV allocates or decodes anything, with a message naming the file and the size.
namespace
{
std::string pngHeaderClaiming(uint32_t w, uint32_t h, uint8_t bit_depth, uint8_t colour_type)
{
    std::string b("\x89PNG\r\n\x1a\n", 8);
    const auto be32 = [&](uint32_t v) {
        for (int s = 24; s >= 0; s -= 8) b.push_back(char((v >> s) & 0xFF));
    };
    be32(13);
    const size_t type_at = b.size();
    b += "IHDR";
    be32(w);
    be32(h);
    b += std::string{char(bit_depth), char(colour_type), 0, 0, 0};
    be32(uint32_t(crc32(0, reinterpret_cast<const Bytef*>(b.data() + type_at), 17)));
    return b;  // no IDAT: without the guard, libpng would still allocate the rows first
}
}  // namespace

TEST_F(Images, HugeImageHeadersAreRefusedBeforeAllocating)
{
    EXPECT_INPUT_ERROR(readDepthImage(write("huge.png", pngHeaderClaiming(100000, 100000, 16, 0))), "huge.png",
                       "claims 100000 x 100000 pixels", "refused before decoding");
    EXPECT_INPUT_ERROR(readLabelImage(write("wide.png", pngHeaderClaiming(40000, 1, 8, 0))), "wide.png",
                       "claims 40000 x 1 pixels");
    EXPECT_INPUT_ERROR(readColorImage(write("big.png", pngHeaderClaiming(9000, 9000, 8, 2))), "big.png",
                       "claims 9000 x 9000");
    EXPECT_INPUT_ERROR(readDepthImage(write("huge.pgm", "P5\n# comment\n100000 100000\n65535\n")), "huge.pgm",
                       "claims 100000 x 100000");
    // JPEG: SOI, an APP0 segment, then SOF0 with height 30000, width 30000.
    const std::string jpeg("\xFF\xD8\xFF\xE0\x00\x04JF\xFF\xC0\x00\x11\x08\x75\x30\x75\x30\x03", 19);
    EXPECT_INPUT_ERROR(readColorImage(write("huge.jpg", jpeg)), "huge.jpg", "claims 30000 x 30000");
    // At the limits the header passes (and the truncated file fails to decode instead).
    EXPECT_INPUT_ERROR(readDepthImage(write("edge.png", pngHeaderClaiming(uint32_t(kMaxImageSide), 1, 16, 0))),
                       "edge.png", "cannot decode");
}

// Formats whose header size is not checked never reach a decoder (the fuzzer found OpenCV's
// JPEG 2000 decoder allocating over a GiB for a small file), even when they decode fine.
TEST_F(Images, OtherFormatsAreRefusedBeforeDecoding)
{
    cv::Mat c(2, 3, CV_8UC3, cv::Scalar(1, 2, 3));
    for (const char* name : {"c.tiff", "c.bmp", "c.webp"})
    {
        ASSERT_TRUE(cv::imwrite(path(name), c)) << name;
        EXPECT_INPUT_ERROR(readColorImage(path(name)), name, "not a PNG, JPEG, PNM or PFM image");
    }
    // A JPEG 2000 codestream signature followed by garbage: refused the same way.
    EXPECT_INPUT_ERROR(readDepthImage(write("x.png", std::string("\0\0\0\x0CjP  \r\n\x87\n\0\0", 14))), "x.png",
                       "not a PNG, JPEG, PNM or PFM image");
    // A PNG cut inside its header: named as truncated, not as another format.
    EXPECT_INPUT_ERROR(readLabelImage(write("cut.png", pngHeaderClaiming(4, 4, 8, 0).substr(0, 12))), "cut.png",
                       "header is truncated");
    // The same pixels as PPM and PNG decode to the same image.
    ASSERT_TRUE(cv::imwrite(path("c.ppm"), c));
    ASSERT_TRUE(cv::imwrite(path("c.png"), c));
    EXPECT_EQ(readColorImage(path("c.ppm")).at(1, 2), readColorImage(path("c.png")).at(1, 2));
    EXPECT_EQ(readColorImage(path("c.ppm")).at(1, 2), (std::array<uint8_t, 3>{3, 2, 1}));
}

// libjpeg only warns at a JPEG cut short, and OpenCV returned a smeared image for it.
TEST_F(Images, AJpegCutShortIsRefusedAndAWholeOneWithPaddingIsRead)
{
    cv::Mat c(64, 80, CV_8UC3);
    cv::randu(c, 0, 255);
    std::vector<uint8_t> jpeg;
    ASSERT_TRUE(cv::imencode(".jpg", c, jpeg));
    const std::string whole(jpeg.begin(), jpeg.end());
    EXPECT_EQ(readColorImage(write("whole.jpg", whole)).width, 80);
    EXPECT_EQ(readColorImage(write("padded.jpg", whole + std::string(16, '\0'))).width, 80);
    EXPECT_INPUT_ERROR(readColorImage(write("cut.jpg", whole.substr(0, whole.size() / 2))), "cut.jpg",
                       "no end-of-image marker");
}

TEST(ImageHeaderSize, PngJpegPnmAndOthers)
{
    const std::string png = pngHeaderClaiming(640, 480, 16, 0);
    EXPECT_EQ(imageHeaderSize(reinterpret_cast<const uint8_t*>(png.data()), png.size()),
              (std::array<int64_t, 2>{640, 480}));
    const std::string pgm = "P2 # c\n 3 2\n";
    EXPECT_EQ(imageHeaderSize(reinterpret_cast<const uint8_t*>(pgm.data()), pgm.size()),
              (std::array<int64_t, 2>{3, 2}));
    const std::string tiff = "II*\0";
    EXPECT_EQ(imageHeaderSize(reinterpret_cast<const uint8_t*>(tiff.data()), tiff.size()),
              (std::array<int64_t, 2>{-1, -1}));
    EXPECT_EQ(imageHeaderSize(reinterpret_cast<const uint8_t*>(png.data()), 20), (std::array<int64_t, 2>{-1, -1}));
    const std::string pfm = "Pf\n4 3\n-1.0\n";
    EXPECT_EQ(imageHeaderSize(reinterpret_cast<const uint8_t*>(pfm.data()), pfm.size()),
              (std::array<int64_t, 2>{4, 3}));
    EXPECT_TRUE(imageFormatKnown(reinterpret_cast<const uint8_t*>(png.data()), 20));
    EXPECT_FALSE(imageFormatKnown(reinterpret_cast<const uint8_t*>(tiff.data()), tiff.size()));
    EXPECT_EQ(imageSizeProblem(8192, 8192), "");
    EXPECT_EQ(imageSizeProblem(-1, -1), "");
    EXPECT_NE(imageSizeProblem(kMaxImageSide + 1, 1), "");
}

}  // namespace pndt::io::test
