// Images: PNG round trips through libpng, depth PNGs, comparison, and bad files.
#include "mvr/core/image.h"
#include "mvr/io/png.h"

#include <cmath>
#include <fstream>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

namespace mvr {
namespace {

std::filesystem::path tempPath(const std::string& name) {
    return std::filesystem::temp_directory_path() /
           fmt::format("mvr-image-test-{}-{}", ::getpid(), name);
}

Image gradient(int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.set(x, y,
                    {std::uint8_t(x * 7), std::uint8_t(y * 13), std::uint8_t(x ^ y),
                     std::uint8_t(255 - x)});
    return img;
}

TEST(Image, PngRoundTripIsExactAndRowZeroIsTop) {
    const Image img = gradient(37, 19);
    const auto path = tempPath("rt.png");
    ASSERT_TRUE(writePng(path, img));
    auto back = readPng(path);
    ASSERT_TRUE(back) << back.status().message();
    EXPECT_EQ(*back, img);
    EXPECT_EQ(back->at(3, 0), img.at(3, 0));  // top row first in the file as in memory
    std::filesystem::remove(path);
}

TEST(Image, DepthPngIsSixteenBitGray) {
    DepthImage d(4, 2);
    d.depth = {0.0f, 0.5f, 1.0f, 0.25f, 1.0f, 1.0f, 0.75f, std::nanf("")};
    const auto path = tempPath("depth.png");
    ASSERT_TRUE(writeDepthPng(path, d));
    auto back = readPng(path);  // converted to RGBA8 on read
    ASSERT_TRUE(back);
    EXPECT_EQ(back->at(0, 0).r, 0);
    EXPECT_EQ(back->at(2, 0).r, 255);
    EXPECT_EQ(back->at(3, 1).r, 255);  // NaN → far
    EXPECT_GT(back->at(1, 0).r, 100);
    std::filesystem::remove(path);
}

/// A PNG's samples as 16-bit gray (PNG_FORMAT_LINEAR_Y), read with libpng's own reader.
std::vector<std::uint16_t> gray16(const std::filesystem::path& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path.c_str())) return {};
    image.format = PNG_FORMAT_LINEAR_Y;
    std::vector<std::uint16_t> out(PNG_IMAGE_SIZE(image) / 2);
    if (!png_image_finish_read(&image, nullptr, out.data(), 0, nullptr)) return {};
    return out;
}

// Every compression mode is lossless: the colour PNGs decode to the image and the 16-bit depth
// PNGs to the samples of libpng's default writer (read with libpng's own reader).
TEST(Image, EveryPngCompressionDecodesToTheSamePixels) {
    Image img(97, 61);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            img.set(x, y, {std::uint8_t((x * x + y) & 255), std::uint8_t((x * y) >> 3),
                           std::uint8_t(std::lround(127 + 120 * std::sin(x * 0.1 + y * 0.07))),
                           std::uint8_t(255 - (x ^ y))});
    DepthImage d(97, 61);
    for (std::size_t i = 0; i < d.depth.size(); ++i) d.depth[i] = float(i % 1013) / 1013.0f;
    const auto reference = tempPath("default-depth.png");
    ASSERT_TRUE(writeDepthPng(reference, d, PngCompression::Default));
    const std::vector<std::uint16_t> samples = gray16(reference);
    ASSERT_EQ(samples.size(), d.depth.size());
    EXPECT_EQ(samples[5], std::uint16_t(std::lround(d.depth[5] * 65535.0f)));
    for (PngCompression c : {PngCompression::Fast, PngCompression::Default, PngCompression::Small}) {
        SCOPED_TRACE(pngCompressionName(c));
        const auto path = tempPath(fmt::format("{}.png", pngCompressionName(c)));
        ASSERT_TRUE(writePng(path, img, c));
        auto back = readPng(path);
        ASSERT_TRUE(back) << back.status().message();
        EXPECT_EQ(*back, img);
        const auto dpath = tempPath(fmt::format("{}-depth.png", pngCompressionName(c)));
        ASSERT_TRUE(writeDepthPng(dpath, d, c));
        EXPECT_EQ(gray16(dpath), samples);
        std::filesystem::remove(path);
        std::filesystem::remove(dpath);
    }
    std::filesystem::remove(reference);
    EXPECT_EQ(*parsePngCompression("small"), PngCompression::Small);
    auto bad = parsePngCompression("tiny");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().message(), "--png-compression tiny: expected fast, default or small");
}

TEST(Image, CompareReportsWorstPixel) {
    Image a(8, 8, {10, 20, 30, 255});
    Image b = a;
    EXPECT_EQ(compareImages(a, b).maxDelta, 0);
    b.set(5, 6, {10, 29, 30, 255});
    b.set(1, 1, {11, 20, 30, 255});
    const ImageDiff d = compareImages(a, b, 1);
    EXPECT_EQ(d.maxDelta, 9);
    EXPECT_EQ(d.worstX, 5);
    EXPECT_EQ(d.worstY, 6);
    EXPECT_EQ(d.differingPixels, 1);  // the 1-off pixel is within the threshold
    EXPECT_EQ(compareImages(a, Image(4, 4)).maxDelta, 256);
}

TEST(Image, BadPngFilesGiveClearErrors) {
    EXPECT_NE(readPng(tempPath("missing.png")).status().message().find("file not found"),
              std::string::npos);
    const auto garbage = tempPath("garbage.png");
    std::ofstream(garbage) << "this is not a png";
    auto r = readPng(garbage);
    EXPECT_EQ(r.status().code(), ErrorCode::Input);
    EXPECT_NE(r.status().message().find("not a readable PNG"), std::string::npos);
    // Every truncated prefix of a real PNG fails cleanly, or (when only the trailing IEND chunk
    // is cut) gives back exactly the whole image: never a partial image.
    const auto good = tempPath("good.png");
    const Image original = gradient(16, 16);
    ASSERT_TRUE(writePng(good, original));
    std::ifstream in(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    int tried = 0;
    for (std::size_t n = 0; n < bytes.size(); n += 3) {
        std::ofstream(garbage, std::ios::binary | std::ios::trunc) << bytes.substr(0, n);
        auto cut = readPng(garbage);
        if (cut) {
            EXPECT_EQ(*cut, original) << "prefix " << n;
            EXPECT_GE(n, bytes.size() - 12) << "only the 12-byte IEND chunk may be missing";
        }
        ++tried;
    }
    EXPECT_GT(tried, 10);
    std::filesystem::remove(garbage);
    std::filesystem::remove(good);
}

std::uint32_t crc32(const std::string& bytes) {
    std::uint32_t c = 0xffffffffu;
    for (unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return ~c;
}

// A PNG whose header claims far more pixels than its bytes can hold is refused before the
// image is allocated (60000 x 60000 RGBA would be 13 GiB).
TEST(Image, PngHeaderClaimingTooMuchIsRefused) {
    const auto good = tempPath("small.png"), big = tempPath("claims.png");
    ASSERT_TRUE(writePng(good, gradient(4, 4)));
    std::ifstream in(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    ASSERT_EQ(bytes.substr(12, 4), "IHDR");
    const unsigned char size[8] = {0, 0, 0xea, 0x60, 0, 0, 0xea, 0x60};  // 60000 x 60000
    bytes.replace(16, 8, reinterpret_cast<const char*>(size), 8);
    const std::uint32_t crc = crc32(bytes.substr(12, 17));
    for (int k = 0; k < 4; ++k) bytes[29 + k] = static_cast<char>(crc >> (24 - 8 * k));
    std::ofstream(big, std::ios::binary) << bytes;
    auto r = readPng(big);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Input);
    EXPECT_NE(r.status().message().find("header claims 60000x60000 pixels but the file's"),
              std::string::npos)
        << r.status().message();
    std::filesystem::remove(good);
    std::filesystem::remove(big);
}

TEST(Image, WritePngToABadPathFails) {
    auto s = writePng("/nonexistent-dir/x.png", Image(2, 2));
    EXPECT_EQ(s.code(), ErrorCode::Output);
    EXPECT_FALSE(writePng(tempPath("empty.png"), Image()));
}

}  // namespace
}  // namespace mvr
