#include "mvr/composite/jpeg.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "mvr/composite/compose.h"
#include "test_views.h"
#include "mvr_test_support.h"

namespace mvr::composite {
namespace {
using namespace mvr::composite::test;

// JPEG tolerance: quality 95, 4:4:4, smooth content → a few levels at most.
constexpr int kJpegTolerance = 8;

std::uint32_t be32(const std::vector<std::uint8_t>& d, std::size_t at) {
    return std::uint32_t(d[at]) << 24 | std::uint32_t(d[at + 1]) << 16 |
           std::uint32_t(d[at + 2]) << 8 | d[at + 3];
}

std::size_t find(const std::vector<std::uint8_t>& d, const std::string& s, std::size_t from = 0) {
    for (std::size_t i = from; i + s.size() <= d.size(); ++i)
        if (std::equal(s.begin(), s.end(), d.begin() + static_cast<std::ptrdiff_t>(i))) return i;
    return std::string::npos;
}

TEST(Jpeg, RoundTripWithinTolerance) {
    const Image img = smoothView(40, 30, 0);
    Result<std::vector<std::uint8_t>> bytes = encodeJpeg(img, 95);
    ASSERT_TRUE(bytes) << bytes.status().message();
    Result<Image> back = decodeJpeg(*bytes, "mem");
    ASSERT_TRUE(back) << back.status().message();
    EXPECT_LE(maxRgbDelta(img, *back), kJpegTolerance);
    EXPECT_EQ(back->at(5, 5).a, 255);
}

TEST(Jpeg, RejectsGarbageAndEveryTruncatedPrefix) {
    Result<std::vector<std::uint8_t>> bytes = encodeJpeg(smoothView(24, 16, 1), 90);
    ASSERT_TRUE(bytes);
    const std::vector<std::uint8_t>& d = *bytes;
    for (std::size_t n = 0; n + 1 < d.size(); ++n) {
        Result<Image> r = decodeJpeg(std::span(d.data(), n), "cut.jpg");
        ASSERT_FALSE(r) << "prefix of " << n << " of " << d.size() << " bytes decoded";
        EXPECT_EQ(r.status().code(), ErrorCode::Input) << n;
        EXPECT_EQ(r.status().message().rfind("cut.jpg: ", 0), 0u) << r.status().message();
    }
    std::vector<std::uint8_t> garbage = d;
    for (std::size_t i = d.size() / 2; i < d.size() - 2; ++i) garbage[i] = std::uint8_t(i * 37);
    EXPECT_FALSE(decodeJpeg(garbage, "garbage.jpg"));
    const std::uint8_t notJpeg[] = {'h', 'e', 'l', 'l', 'o'};
    Result<Image> r = decodeJpeg(notJpeg, "hello.txt");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().message(), "hello.txt: not a JPEG file (no SOI marker FF D8 FF)");
}

// A header that claims far more pixels than the file can code is refused before the image is
// allocated (16000 x 16000 RGBA would be 1 GiB from a file of a few hundred bytes).
TEST(Jpeg, HeaderClaimingTooMuchIsRefused) {
    Result<std::vector<std::uint8_t>> bytes = encodeJpeg(smoothView(16, 16, 1), 90);
    ASSERT_TRUE(bytes);
    std::vector<std::uint8_t> d = *bytes;
    std::size_t sof = 0;
    for (std::size_t i = 2; i + 9 < d.size() && !sof; ++i)
        if (d[i] == 0xff && (d[i + 1] == 0xc0 || d[i + 1] == 0xc2)) sof = i;
    ASSERT_NE(sof, 0u);
    for (std::size_t at : {sof + 5, sof + 7}) d[at] = 16000 >> 8, d[at + 1] = 16000 & 0xff;
    Result<Image> r = decodeJpeg(d, "claims.jpg");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Input);
    EXPECT_NE(r.status().message().find("claims.jpg: JPEG header claims 16000x16000 pixels"),
              std::string::npos)
        << r.status().message();
}

TEST(Jpeg, EncodeRejectsBadArguments) {
    EXPECT_EQ(encodeJpeg(Image(), 90).status().code(), ErrorCode::Usage);
    EXPECT_EQ(encodeJpeg(smoothView(4, 4, 0), 0).status().code(), ErrorCode::Usage);
    EXPECT_EQ(encodeJpeg(smoothView(4, 4, 0), 101).status().code(), ErrorCode::Usage);
}

TEST(Mpo, StructureFollowsCipaDc007) {
    const std::vector<Image> views = {smoothView(32, 24, 0), smoothView(32, 24, 2)};
    ComposeOptions o;
    o.baseline = 0.065;
    o.convergence = 2.0;
    Result<std::vector<std::uint8_t>> mpo = encodeMpo(views, o);
    ASSERT_TRUE(mpo) << mpo.status().message();
    const std::vector<std::uint8_t>& d = *mpo;
    ASSERT_GE(d.size(), 100u);
    EXPECT_EQ(d[0], 0xFF);
    EXPECT_EQ(d[1], 0xD8);
    EXPECT_EQ(d[2], 0xFF);
    EXPECT_EQ(d[3], 0xE1);  // APP1 Exif first
    const std::size_t mpf = find(d, std::string("MPF\0", 4));
    ASSERT_NE(mpf, std::string::npos);
    EXPECT_EQ(d[mpf - 4], 0xFF);
    EXPECT_EQ(d[mpf - 3], 0xE2);    // in an APP2 segment
    const std::size_t h = mpf + 4;  // MP header
    EXPECT_EQ(std::string(d.begin() + h, d.begin() + h + 4), std::string("MM\0\x2A", 4));
    // MP Index IFD: MPFVersion, NumberOfImages = 2, MPEntry (32 bytes).
    const std::size_t ifd = h + be32(d, h + 4);
    EXPECT_EQ(d[ifd] << 8 | d[ifd + 1], 3);
    EXPECT_EQ(d[ifd + 2] << 8 | d[ifd + 3], 0xB000);
    EXPECT_EQ(std::string(d.begin() + ifd + 10, d.begin() + ifd + 14), "0100");
    EXPECT_EQ(d[ifd + 14] << 8 | d[ifd + 15], 0xB001);
    EXPECT_EQ(be32(d, ifd + 22), 2u);
    EXPECT_EQ(d[ifd + 26] << 8 | d[ifd + 27], 0xB002);
    EXPECT_EQ(be32(d, ifd + 30), 32u);
    const std::size_t entries = h + be32(d, ifd + 34);
    EXPECT_EQ(be32(d, entries) & 0x00FFFFFFu, 0x020002u);    // multi-frame disparity
    EXPECT_EQ(be32(d, entries) & 0x20000000u, 0x20000000u);  // representative
    EXPECT_EQ(be32(d, entries + 16) & 0x00FFFFFFu, 0x020002u);
    const std::uint32_t size1 = be32(d, entries + 4), size2 = be32(d, entries + 20);
    EXPECT_EQ(be32(d, entries + 8), 0u);
    const std::size_t start2 = h + be32(d, entries + 24);
    EXPECT_EQ(start2, size1);  // the second image follows the first
    EXPECT_EQ(size1 + size2, d.size());
    EXPECT_EQ(d[start2], 0xFF);
    EXPECT_EQ(d[start2 + 1], 0xD8);
    EXPECT_EQ(d[size1 - 2], 0xFF);
    EXPECT_EQ(d[size1 - 1], 0xD9);  // first image ends with EOI
    // The second image has its own MP Attribute IFD.
    EXPECT_NE(find(d, std::string("MPF\0", 4), start2), std::string::npos);

    Result<std::vector<MpoImageRange>> ranges = mpoImageRanges(d, "mem");
    ASSERT_TRUE(ranges) << ranges.status().message();
    ASSERT_EQ(ranges->size(), 2u);
    EXPECT_EQ((*ranges)[1].offset, start2);
    EXPECT_EQ((*ranges)[1].size, size2);
}

TEST(Mpo, RoundTripKeepsViewOrderAndPixels) {
    const std::vector<Image> views = {smoothView(32, 24, 0), smoothView(32, 24, 2),
                                      smoothView(32, 24, 4)};
    Result<std::vector<std::uint8_t>> mpo = encodeMpo(views, {});
    ASSERT_TRUE(mpo);
    Result<std::vector<Image>> back = decodeMpo(*mpo, "mem");
    ASSERT_TRUE(back) << back.status().message();
    ASSERT_EQ(back->size(), 3u);
    for (int v = 0; v < 3; ++v) EXPECT_LE(maxRgbDelta(views[v], (*back)[v]), kJpegTolerance) << v;
    ComposeOptions swap;
    swap.swapEyes = true;
    Result<std::vector<std::uint8_t>> swapped = encodeMpo(views, swap);
    ASSERT_TRUE(swapped);
    Result<std::vector<Image>> backSwapped = decodeMpo(*swapped, "mem");
    ASSERT_TRUE(backSwapped);
    EXPECT_LE(maxRgbDelta(views[2], (*backSwapped)[0]), kJpegTolerance);
    EXPECT_LE(maxRgbDelta(views[0], (*backSwapped)[2]), kJpegTolerance);
}

TEST(Mpo, TruncatedFilesAreErrors) {
    const std::vector<Image> views = {smoothView(16, 8, 0), smoothView(16, 8, 3)};
    Result<std::vector<std::uint8_t>> mpo = encodeMpo(views, {});
    ASSERT_TRUE(mpo);
    const std::vector<std::uint8_t>& d = *mpo;
    for (std::size_t n = 0; n < d.size(); n += 7) {
        Result<std::vector<Image>> r = decodeMpo(std::span(d.data(), n), "cut.mpo");
        ASSERT_FALSE(r) << n;
        EXPECT_EQ(r.status().code(), ErrorCode::Input);
    }
    Result<std::vector<Image>> last = decodeMpo(std::span(d.data(), d.size() - 1), "cut.mpo");
    ASSERT_FALSE(last);
    EXPECT_EQ(last.status().message().rfind("cut.mpo", 0), 0u) << last.status().message();
}

TEST(Mpo, SurvivesRandomCorruption) {
    // Seeded byte flips, half of them in the Exif/MPF header area: decoding must return an
    // image list or an Input error, never crash (run under ASan/UBSan in CI).
    const std::vector<Image> views = {smoothView(16, 8, 0), smoothView(16, 8, 3)};
    Result<std::vector<std::uint8_t>> mpo = encodeMpo(views, {});
    ASSERT_TRUE(mpo);
    std::uint32_t seed = 12345;
    const auto next = [&seed] { return seed = seed * 1664525u + 1013904223u; };
    for (int round = 0; round < 400; ++round) {
        std::vector<std::uint8_t> d = *mpo;
        const int flips = 1 + static_cast<int>(next() % 8);
        for (int f = 0; f < flips; ++f) {
            const std::size_t span =
                (round % 2 == 0) ? std::min<std::size_t>(d.size(), 200) : d.size();
            d[next() % span] = static_cast<std::uint8_t>(next() >> 24);
        }
        Result<std::vector<Image>> r = decodeMpo(d, "fuzz.mpo");
        if (!r) {
            EXPECT_TRUE(r.status().code() == ErrorCode::Input ||
                        r.status().code() == ErrorCode::Unsupported)  // e.g. now "CMYK"
                << r.status().message();
        }
    }
}

TEST(Mpo, PlainJpegIsOneView) {
    Result<std::vector<std::uint8_t>> jpeg = encodeJpeg(smoothView(8, 8, 0), 90);
    ASSERT_TRUE(jpeg);
    Result<std::vector<Image>> views = decodeMpo(*jpeg, "one.jpg");
    ASSERT_TRUE(views);
    EXPECT_EQ(views->size(), 1u);
}

TEST(Mpo, RejectsBadArguments) {
    EXPECT_FALSE(encodeMpo(std::vector<Image>{smoothView(8, 8, 0)}, {}));
    ComposeOptions o;
    o.baseViewpoint = 3;
    const std::vector<Image> two = {smoothView(8, 8, 0), smoothView(8, 8, 1)};
    Result<std::vector<std::uint8_t>> r = encodeMpo(two, o);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().message(),
              "mvr::composite::encodeMpo(): base viewpoint 3 of 2 views (expected 1..2)");
    o = {};
    o.baseline = -1;
    EXPECT_FALSE(encodeMpo(two, o));
}

TEST(Jps, RightViewOnTheLeftAndRoundTrip) {
    const Image left = smoothView(20, 10, 0), right = smoothView(20, 10, 4);
    Result<std::vector<std::uint8_t>> jps = encodeJps(left, right, 95);
    ASSERT_TRUE(jps);
    const std::size_t app3 = find(*jps, "_JPSJPS_");
    ASSERT_NE(app3, std::string::npos);
    EXPECT_EQ((*jps)[app3 - 4], 0xFF);
    EXPECT_EQ((*jps)[app3 - 3], 0xE3);
    // descriptor length 4; separation 0, flags 0 (right image first), side by side, stereo
    const std::uint8_t descriptor[] = {0, 4, 0, 0, 2, 1};
    for (int i = 0; i < 6; ++i) EXPECT_EQ((*jps)[app3 + 8 + i], descriptor[i]) << i;
    Result<Image> picture = decodeJpeg(*jps, "mem.jps");
    ASSERT_TRUE(picture);
    ASSERT_EQ(picture->width, 40);
    ASSERT_EQ(picture->height, 10);
    // Left half is the right view.
    EXPECT_LE(std::abs(picture->at(3, 3).b - right.at(3, 3).b), kJpegTolerance);
    EXPECT_LE(std::abs(picture->at(23, 3).b - left.at(3, 3).b), kJpegTolerance);
    Result<std::vector<Image>> views = splitJps(*picture, "mem.jps");
    ASSERT_TRUE(views);
    ASSERT_EQ(views->size(), 2u);
    EXPECT_LE(maxRgbDelta((*views)[0], left), kJpegTolerance);
    EXPECT_LE(maxRgbDelta((*views)[1], right), kJpegTolerance);
    EXPECT_FALSE(splitJps(smoothView(5, 2, 0), "odd.jps"));
}

// exiftool (Debian libimage-exiftool-perl) must read mvr's MPO: 2 images and the MP tags.
std::string run(const std::string& command) { return ::mvr::test::runShell(command).output; }

TEST(Mpo, ExiftoolReadsTwoImagesAndTheMpTagsAndTheJpsDescriptor) {
    if (std::system("exiftool -ver > /dev/null 2>&1") != 0)
        MVR_SKIP(ToolMissing) << "exiftool not installed (Debian: libimage-exiftool-perl)";
    const auto dir = freshDir("exiftool");
    const std::vector<Image> views = {smoothView(32, 24, 0), smoothView(32, 24, 2)};
    ComposeOptions o;
    o.baseline = 0.065;
    o.convergence = 2.0;
    Result<std::filesystem::path> path = writeComposite("mpo", views, o, dir);
    ASSERT_TRUE(path) << path.status().message();
    EXPECT_EQ(path->filename(), "mpo.mpo");
    const std::string out = run("exiftool -a -s -ee -G3 '" + path->string() + "'");
    const auto has = [&](const std::string& line) {
        EXPECT_NE(out.find(line), std::string::npos) << "missing '" << line << "' in:\n" << out;
    };
    has("NumberOfImages                  : 2");
    has("MPImageType                     : Multi-frame Disparity");
    has("MPImage2                        : (Binary data");
    has("[Main]          MPIndividualNum                 : 1");
    has("[Doc2]          MPIndividualNum                 : 2");
    has("BaseViewpointNum                : 1");
    has("BaselineLength                  : 0.065");
    has("ConvergenceAngle                : 1.86");  // 2·atan(0.0325 / 2) in degrees
    has("[Doc2]          AxisDistanceX                   : 0.065");
    EXPECT_EQ(out.find("Warning"), std::string::npos) << out;
    EXPECT_EQ(out.find("Error"), std::string::npos) << out;
    Result<std::filesystem::path> jps = writeComposite("jps", views, o, dir);
    ASSERT_TRUE(jps);
    const std::string jpsOut = run("exiftool -a -s '" + jps->string() + "'");
    EXPECT_NE(jpsOut.find("JPSLayout                       : Side By Side"), std::string::npos)
        << jpsOut;
    EXPECT_NE(jpsOut.find("JPSType                         : Stereo"), std::string::npos) << jpsOut;
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mvr::composite
