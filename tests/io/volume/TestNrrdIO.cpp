// Tests for io/volume/NrrdIO.h: round trips, sample types, encodings, endianness,
// detached headers, geometry, and a table of malformed files.
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/volume/NrrdIO.h"
#include "io/volume/VolumeReader.h"
#include "kernels/base/Error.h"
#include "tests/support/Bzip2Bytes.h"
#include "tests/support/FileBytes.h"
#include "tests/support/InputErrorExpectation.h"
#include "tests/support/MaskCounts.h"
#include "tests/support/TempDir.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

/// gzip (windowBits 15 + 16) or zlib (15) compression of `bytes`.
std::string compress(const std::string& bytes, bool gzipHeader = true) {
    z_stream stream{};
    EXPECT_EQ(
        deflateInit2(&stream, 6, Z_DEFLATED, gzipHeader ? 15 + 16 : 15, 8, Z_DEFAULT_STRATEGY),
        Z_OK);
    std::string out(deflateBound(&stream, uLong(bytes.size())) + 64, '\0');
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    stream.avail_in = uInt(bytes.size());
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = uInt(out.size());
    EXPECT_EQ(deflate(&stream, Z_FINISH), Z_STREAM_END);
    out.resize(stream.total_out);
    deflateEnd(&stream);
    return out;
}

/// An attached NRRD: magic, the given field lines, a blank line, the data.
std::string nrrd(const std::string& fields, const std::string& data) {
    return "NRRD0004\n" + fields + "\n" + data;
}

std::string basicFields(const std::string& type, const std::string& sizes,
                        const std::string& encoding, const std::string& extra = "") {
    return "type: " + type + "\ndimension: 3\nsizes: " + sizes + "\nencoding: " + encoding + "\n" +
           extra;
}

/// 4 x 3 x 2 uint8 samples: voxels 1 and 23 are object.
std::string twoObjectVoxels() {
    std::string data(4 * 3 * 2, '\0');
    data[1] = 1;
    data[23] = 7;
    return data;
}

/// The file reads as twoObjectVoxels() does.
void expectTwoObjectVoxels(const fs::path& file) {
    const MaskVolume mask = readNrrdMask(file);
    EXPECT_EQ(mask[1], 1) << file;
    EXPECT_EQ(mask[23], 1) << file;
    EXPECT_EQ(countNonzero(mask), 2u) << file;
}

LabelVolume makeLabels() {
    LabelVolume labels(Dims{5, 7, 3});
    for (int z = 0; z < 3; ++z)
        for (int y = 0; y < 7; ++y)
            for (int x = 0; x < 5; ++x)
                labels(x, y, z) =
                    std::uint16_t((x * 7 + y * 31 + z * 1009) % 4 == 0 ? 0 : x + 10 * y + 100 * z);
    labels(4, 6, 2) = 65535;  // high byte set: catches byte order mistakes
    labels(0, 0, 0) = 0;
    return labels;
}

VolumeGeometry obliqueGeometry() {
    VolumeGeometry geometry;
    geometry.spaceName = "left-posterior-superior";
    geometry.origin = {-12.5, 3.25, 100.125};
    geometry.directions = {{{0.5, 0.1, 0.0}, {-0.1, 0.75, 0.0}, {0.0, 0.0, 1.2}}};
    return geometry;
}

void expectSameGeometry(const VolumeGeometry& a, const VolumeGeometry& b) {
    EXPECT_EQ(a.spaceName, b.spaceName);
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(a.origin[c], b.origin[c]);
    for (int axis = 0; axis < 3; ++axis)
        for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(a.directions[axis][c], b.directions[axis][c]);
}

}  // namespace

TEST(NrrdIO, LabelsRoundTripKeepsValuesDimsAndGeometry) {
    test::TempDir dir;
    LabelVolume labels = makeLabels();
    labels.geometry = obliqueGeometry();
    writeNrrdLabels(dir / "labels.nrrd", labels);
    const LabelVolume back = readNrrdLabels(dir / "labels.nrrd");
    ASSERT_EQ(back.dims(), (Dims{5, 7, 3}));
    EXPECT_EQ(back.values(), labels.values());
    expectSameGeometry(back.geometry, labels.geometry);
    // The file is gzip encoded, uint16, little endian: what teem/Slicer expect.
    const std::string text = fileBytes(dir / "labels.nrrd");
    EXPECT_NE(text.find("encoding: gzip\n"), std::string::npos);
    EXPECT_NE(text.find("type: uint16\n"), std::string::npos);
    EXPECT_NE(text.find("endian: little\n"), std::string::npos);
    EXPECT_NE(text.find("space: left-posterior-superior\n"), std::string::npos);
}

TEST(NrrdIO, MaskRoundTripAndLabelsReadAsMask) {
    test::TempDir dir;
    MaskVolume mask(Dims{5, 7, 3});
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = (i * 2654435761u) % 3 == 0;
    mask.geometry = VolumeGeometry::uniform(0.3, {1.0, -2.0, 3.5});
    writeNrrdMask(dir / "mask.nrrd", mask);
    const MaskVolume back = readNrrdMask(dir / "mask.nrrd");
    ASSERT_EQ(back.dims(), mask.dims());
    EXPECT_EQ(back.values(), mask.values());
    expectSameGeometry(back.geometry, mask.geometry);

    const LabelVolume labels = makeLabels();
    writeNrrdLabels(dir / "labels.nrrd", labels);
    const MaskVolume fromLabels = readNrrdMask(dir / "labels.nrrd");
    for (std::size_t i = 0; i < labels.size(); ++i)
        ASSERT_EQ(fromLabels[i], labels[i] != 0 ? 1 : 0) << i;
}

TEST(NrrdIO, NoSpaceNameWritesSpaceDimensionAndRoundTrips) {
    test::TempDir dir;
    LabelVolume labels = makeLabels();
    labels.geometry = VolumeGeometry::uniform(0.125, {4, 5, 6});
    writeNrrdLabels(dir / "labels.nrrd", labels);
    EXPECT_NE(fileBytes(dir / "labels.nrrd").find("space dimension: 3\n"), std::string::npos);
    expectSameGeometry(readNrrdLabels(dir / "labels.nrrd").geometry, labels.geometry);
}

TEST(NrrdIO, FirstAxisIsXFastest) {
    test::TempDir dir;
    std::string data(5 * 7 * 3, '\0');
    data[4 + 5 * (1 + 7 * 2)] = 9;  // (x, y, z) = (4, 1, 2)
    writeBytes(dir / "one.nrrd", nrrd(basicFields("uchar", "5 7 3", "raw"), data));
    const MaskVolume mask = readNrrdMask(dir / "one.nrrd");
    ASSERT_EQ(mask.dims(), (Dims{5, 7, 3}));
    EXPECT_EQ(mask(4, 1, 2), 1);
    EXPECT_EQ(countNonzero(mask), 1u);
}

TEST(NrrdIO, BigAndLittleEndianUint16) {
    test::TempDir dir;
    std::string data(2 * 2 * 1 * 1, '\0');
    data[0] = 0x01;
    data[1] = 0x02;  // first sample bytes 01 02
    data[2] = 0x00;
    data[3] = 0x05;  // second sample bytes 00 05
    writeBytes(dir / "big.nrrd",
               nrrd(basicFields("unsigned short", "2 1 1", "raw", "endian: big\n"), data));
    writeBytes(dir / "little.nrrd",
               nrrd(basicFields("uint16", "2 1 1", "raw", "endian: little\n"), data));
    const LabelVolume big = readNrrdLabels(dir / "big.nrrd");
    const LabelVolume little = readNrrdLabels(dir / "little.nrrd");
    EXPECT_EQ(big[0], 0x0102);
    EXPECT_EQ(big[1], 0x0005);
    EXPECT_EQ(little[0], 0x0201);
    EXPECT_EQ(little[1], 0x0500);
}

TEST(NrrdIO, GzipZlibAndGzSpellings) {
    test::TempDir dir;
    const std::string data = twoObjectVoxels();
    writeBytes(dir / "gzip.nrrd", nrrd(basicFields("uint8", "4 3 2", "gzip"), compress(data)));
    writeBytes(dir / "gz.nrrd", nrrd(basicFields("uint8", "4 3 2", "gz"), compress(data)));
    writeBytes(dir / "zlib.nrrd",
               nrrd(basicFields("uint8", "4 3 2", "gzip"), compress(data, false)));
    // Two concatenated gzip members (as `cat a.gz b.gz` gives).
    writeBytes(dir / "members.nrrd",
               nrrd(basicFields("uint8", "4 3 2", "gzip"),
                    compress(data.substr(0, 10)) + compress(data.substr(10))));
    for (const char* name : {"gzip.nrrd", "gz.nrrd", "zlib.nrrd", "members.nrrd"}) {
        expectTwoObjectVoxels(dir / name);
    }
}

TEST(NrrdIO, GzipBigEndianUint16Labels) {
    test::TempDir dir;
    std::string data(3 * 1 * 1 * 2, '\0');
    data[2] = 0x12;
    data[3] = 0x34;
    writeBytes(dir / "big.nrrd",
               nrrd(basicFields("ushort", "3 1 1", "gzip", "endian: big\n"), compress(data)));
    const LabelVolume labels = readNrrdLabels(dir / "big.nrrd");
    EXPECT_EQ(labels[0], 0);
    EXPECT_EQ(labels[1], 0x1234);
    EXPECT_EQ(labels[2], 0);
}

TEST(NrrdIO, AllSampleTypesNonzeroIsObject) {
    test::TempDir dir;
    struct Case {
        const char* type;
        std::vector<std::uint8_t> zero, nonzero;  // little-endian sample bytes
    };
    const float negativeZero = -0.0f, half = 0.5f;
    const double tiny = 1e-300;
    std::vector<std::uint8_t> negativeZeroBytes(4), halfBytes(4), tinyBytes(8);
    std::memcpy(negativeZeroBytes.data(), &negativeZero, 4);
    std::memcpy(halfBytes.data(), &half, 4);
    std::memcpy(tinyBytes.data(), &tiny, 8);
    const std::vector<Case> cases = {
        {"signed char", {0}, {0xff}},
        {"int8", {0}, {0x80}},
        {"uchar", {0}, {1}},
        {"unsigned char", {0}, {255}},
        {"uint8_t", {0}, {2}},
        {"short", {0, 0}, {0xff, 0xff}},
        {"signed short int", {0, 0}, {0, 1}},
        {"ushort", {0, 0}, {0, 0x80}},
        {"unsigned short int", {0, 0}, {1, 0}},
        {"int", {0, 0, 0, 0}, {0, 0, 0, 0x80}},
        {"uint32", {0, 0, 0, 0}, {0, 0, 1, 0}},
        {"unsigned   int", {0, 0, 0, 0}, {0, 1, 0, 0}},
        {"long long", {0, 0, 0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0, 0, 1}},
        {"uint64", {0, 0, 0, 0, 0, 0, 0, 0}, {1, 0, 0, 0, 0, 0, 0, 0}},
        {"float", negativeZeroBytes, halfBytes},  // -0.0 is zero
        {"double", {0, 0, 0, 0, 0, 0, 0, 0}, tinyBytes},
    };
    for (const auto& c : cases) {
        std::string data;
        data.append(c.zero.begin(), c.zero.end());
        data.append(c.nonzero.begin(), c.nonzero.end());
        data.append(c.zero.begin(), c.zero.end());
        const std::string extra = c.zero.size() > 1 ? "endian: little\n" : "";
        const fs::path file = dir / "typed.nrrd";
        writeBytes(file, nrrd(basicFields(c.type, "3 1 1", "raw", extra), data));
        const MaskVolume mask = readNrrdMask(file);
        EXPECT_EQ(mask[0], 0) << c.type;
        EXPECT_EQ(mask[1], 1) << c.type;
        EXPECT_EQ(mask[2], 0) << c.type;
    }
}

TEST(NrrdIO, DetachedHeaderWithRelativeDataFile) {
    test::TempDir dir;
    fs::create_directories(dir / "sub");
    std::string data(2 * 3 * 4, '\0');
    data[5] = 1;
    writeBytes(dir / "sub" / "volume.raw", data);
    writeBytes(dir / "volume.nhdr",
               "NRRD0005\n" + basicFields("uint8", "2 3 4", "raw") + "data file: sub/volume.raw\n");
    MaskVolume mask = readNrrdMask(dir / "volume.nhdr");
    EXPECT_EQ(mask[5], 1);
    EXPECT_EQ(countNonzero(mask), 1u);

    // Detached gzip data, through the format dispatcher.
    writeBytes(dir / "sub" / "volume.raw.gz", compress(data));
    writeBytes(dir / "gz.nhdr", "NRRD0004\n" + basicFields("uint8", "2 3 4", "gzip") +
                                    "datafile: sub/volume.raw.gz\n\n");
    mask = readVolume(dir / "gz.nhdr");
    EXPECT_EQ(mask[5], 1);
    EXPECT_EQ(countNonzero(mask), 1u);
}

TEST(NrrdIO, AHandWrittenHeaderSavedByAWindowsEditor) {
    // A detached header is written by hand. With a UTF-8 byte order mark
    // (Notepad) it was "wrong magic '???NRRD0004'", a header the user sees
    // start with NRRD0004; as UTF-16 "wrong magic '??N?R?R?D?0?0?0?'", with
    // classic Mac OS line ends "wrong magic 'NRRD0004?type: u'".
    test::TempDir dir;
    writeBytes(dir / "volume.raw", twoObjectVoxels());
    const std::string header =
        "NRRD0004\r\n" + basicFields("uint8", "4 3 2", "raw") + "data file: volume.raw\r\n";
    writeBytes(dir / "bom.nhdr", "\xEF\xBB\xBF" + header);
    expectTwoObjectVoxels(dir / "bom.nhdr");
    // An attached header too: the data still starts after the blank line.
    writeBytes(dir / "bom.nrrd",
               "\xEF\xBB\xBF" + nrrd(basicFields("uint8", "4 3 2", "raw"), twoObjectVoxels()));
    expectTwoObjectVoxels(dir / "bom.nrrd");

    std::string utf16 = "\xFF\xFE";
    for (char c : header) utf16 += std::string{c, '\0'};
    writeBytes(dir / "utf16.nhdr", utf16);
    expectInputError([&] { readNrrdMask(dir / "utf16.nhdr"); }, "utf16.nhdr",
                     "is UTF-16 text (it starts with a UTF-16 byte order mark); save it as UTF-8");
    std::string classicMac = header;
    std::replace(classicMac.begin(), classicMac.end(), '\n', '\r');
    classicMac.erase(std::unique(classicMac.begin(), classicMac.end(),
                                 [](char a, char b) { return a == '\r' && b == '\r'; }),
                     classicMac.end());
    writeBytes(dir / "mac.nhdr", classicMac);
    expectInputError([&] { readNrrdMask(dir / "mac.nhdr"); }, "mac.nhdr",
                     "ends its lines with a carriage return alone (classic Mac OS text)");
}

TEST(NrrdIO, ByteSkipBeforeRawAndDecompressedData) {
    // Valid files that were refused ("byte skip '-1' is not supported"):
    // pynrrd's BallBinary30x30x30_byteskip_minus_one.nhdr, a detached header
    // whose raw data is the file's last bytes (-1), and skips of N bytes
    // before raw data and before the decompressed gzip data, as teem reads them.
    test::TempDir dir;
    const std::string data = twoObjectVoxels();
    const std::string header = "another format's header";
    writeBytes(dir / "volume.img", header + data);
    writeBytes(dir / "end.nhdr", "NRRD0004\n" + basicFields("uint8", "4 3 2", "raw") +
                                     "byte skip: -1\ndata file: volume.img\n");
    writeBytes(dir / "skip.nhdr", "NRRD0004\n" + basicFields("uint8", "4 3 2", "raw") +
                                      "byte skip: " + std::to_string(header.size()) +
                                      "\ndata file: volume.img\n");
    writeBytes(dir / "attached.nrrd",
               nrrd(basicFields("uint8", "4 3 2", "raw") + "byteskip: 3\n", "abc" + data));
    writeBytes(dir / "gzip.nrrd", nrrd(basicFields("uint8", "4 3 2", "gzip") + "byte skip: 3\n",
                                       compress("abc" + data)));
    for (const char* name : {"end.nhdr", "skip.nhdr", "attached.nrrd", "gzip.nrrd"}) {
        expectTwoObjectVoxels(dir / name);
    }

    writeBytes(dir / "minus2.nrrd",
               nrrd(basicFields("uint8", "4 3 2", "raw") + "byte skip: -2\n", data));
    expectInputError([&] { readNrrdMask(dir / "minus2.nrrd"); }, "minus2.nrrd",
                     "byte skip '-2' is invalid (it is -1 or at least 0)");
    writeBytes(dir / "past.nrrd",
               nrrd(basicFields("uint8", "4 3 2", "raw") + "byte skip: 25\n", data));
    expectInputError([&] { readNrrdMask(dir / "past.nrrd"); }, "past.nrrd",
                     "data is too short: byte skip 25 is past the 24 bytes of data");
    writeBytes(dir / "end-short.nrrd",
               nrrd(basicFields("uint8", "4 3 2", "raw") + "byte skip: -1\n", data.substr(1)));
    expectInputError([&] { readNrrdMask(dir / "end-short.nrrd"); }, "end-short.nrrd",
                     "data is too short: 23 bytes");
    writeBytes(dir / "gzip-short.nrrd",
               nrrd(basicFields("uint8", "4 3 2", "gzip") + "byte skip: 3\n", compress(data)));
    expectInputError([&] { readNrrdMask(dir / "gzip-short.nrrd"); }, "gzip-short.nrrd",
                     "data is too short");
}

/// One volume's samples of one type, in every encoding: the raw bytes
/// (little endian), ascii numbers and hex digits.
struct EncodedSamples {
    std::string type;
    std::string raw;
    std::string ascii;
    std::string hex;
};

template <typename Sample>
EncodedSamples encodeSamples(const std::string& type, const std::vector<Sample>& values,
                             const std::vector<std::string>& asciiValues) {
    EncodedSamples encoded{type, {}, {}, {}};
    for (std::size_t i = 0; i < values.size(); ++i) {
        char bytes[sizeof(Sample)];
        std::memcpy(bytes, &values[i], sizeof(Sample));
        encoded.raw.append(bytes, sizeof(Sample));
        // Line breaks, tabs and teem's commas between the numbers.
        encoded.ascii += asciiValues[i] + (i % 5 == 4 ? "\n" : i % 3 == 0 ? ",\t" : " ");
    }
    static const char kDigits[] = "0123456789abcdefABCDEF";
    for (std::size_t i = 0; i < encoded.raw.size(); ++i) {
        const auto byte = std::uint8_t(encoded.raw[i]);
        // Either case, whitespace between digits and between bytes.
        const bool upper = i % 2 == 1;
        const auto digit = [&](int value) {
            return kDigits[value < 10 || !upper ? value : value + 6];
        };
        encoded.hex += digit(byte >> 4);
        if (i % 7 == 3) encoded.hex += ' ';
        encoded.hex += digit(byte & 15);
        encoded.hex += i % 16 == 15 ? "\n" : (i % 4 == 0 ? "  " : "");
    }
    return encoded;
}

TEST(NrrdIO, AsciiHexAndBzip2GiveTheMaskOfRaw) {
    // Valid files that were refused ("unsupported encoding"): teem, ITK and
    // pynrrd write every encoding of the format definition.
    test::TempDir dir;
    const std::string sizes = "4 3 2";
    std::vector<std::uint8_t> bytes(24);
    std::vector<std::uint16_t> shorts(24);
    std::vector<float> floats(24);
    std::vector<std::string> byteText, shortText, floatText;
    for (int i = 0; i < 24; ++i) {
        bytes[i] = std::uint8_t(i % 3 == 0 ? 0 : 200 + i);
        shorts[i] = std::uint16_t(i % 4 == 1 ? 0 : 256 * i + 1);  // high bytes set: byte order
        floats[i] = i % 5 == 0 ? 0.0f : 0.25f * float(i - 12);
        byteText.push_back(std::to_string(bytes[i]));
        shortText.push_back(i == 2 ? "+513.0" : std::to_string(shorts[i]));  // pynrrd's %.17g
        floatText.push_back(std::to_string(floats[i]));
    }
    floats[5] = -0.0f;  // not object
    floatText[5] = "-0";
    floats[7] = std::numeric_limits<float>::quiet_NaN();  // object
    floatText[7] = "nan";
    floats[9] = 1e-3f;
    floatText[9] = "1e-3";
    const std::vector<EncodedSamples> cases = {
        encodeSamples<std::uint8_t>("uint8", bytes, byteText),
        encodeSamples<std::uint16_t>("uint16", shorts, shortText),
        encodeSamples<float>("float", floats, floatText),
    };
    for (const auto& c : cases) {
        const std::string endian = c.type == "uint8" ? "" : "endian: little\n";
        writeBytes(dir / "raw.nrrd", nrrd(basicFields(c.type, sizes, "raw", endian), c.raw));
        const MaskVolume raw = readNrrdMask(dir / "raw.nrrd");
        ASSERT_GT(countNonzero(raw), 4u) << c.type;
        ASSERT_LT(countNonzero(raw), 24u) << c.type;
        const std::vector<std::pair<std::string, std::string>> files = {
            // ascii needs no endian field: its numbers have no byte order.
            {"ascii.nrrd", nrrd(basicFields(c.type, sizes, "ascii"), c.ascii)},
            {"text.nrrd", nrrd(basicFields(c.type, sizes, "text"), c.ascii)},
            {"txt.nrrd", nrrd(basicFields(c.type, sizes, "TXT"), c.ascii + "\n\n")},
            {"hex.nrrd", nrrd(basicFields(c.type, sizes, "hex", endian), c.hex)},
            {"bzip2.nrrd",
             nrrd(basicFields(c.type, sizes, "bzip2", endian), test::bzip2Bytes(c.raw))},
            {"bz2.nrrd", nrrd(basicFields(c.type, sizes, "bz2", endian), test::bzip2Bytes(c.raw))},
            // pbzip2 writes one stream per block.
            {"streams.nrrd",
             nrrd(basicFields(c.type, sizes, "bzip2", endian),
                  test::bzip2Bytes(c.raw.substr(0, 5)) + test::bzip2Bytes(c.raw.substr(5)))},
        };
        for (const auto& [name, content] : files) {
            writeBytes(dir / name, content);
            const MaskVolume mask = readNrrdMask(dir / name);
            EXPECT_EQ(mask.values(), raw.values()) << c.type << " " << name;
            if (c.type != "float")
                EXPECT_EQ(readNrrdLabels(dir / name).values(),
                          readNrrdLabels(dir / "raw.nrrd").values())
                    << c.type << " " << name;
        }
    }
    // Big-endian hex and bzip2 are swapped like raw.
    writeBytes(dir / "big.nrrd",
               nrrd(basicFields("uint16", "2 1 1", "hex", "endian: big\n"), "0102 FFfe"));
    const LabelVolume big = readNrrdLabels(dir / "big.nrrd");
    EXPECT_EQ(big[0], 0x0102);
    EXPECT_EQ(big[1], 0xfffe);
}

TEST(NrrdIO, LineSkipAndByteSkipInEveryEncoding) {
    test::TempDir dir;
    const std::string data = twoObjectVoxels();
    const std::string ascii = "0 1 0 0 0 0\n0 0 0 0 0 0\n0 0 0 0 0 0\n0 0 0 0 0 7\n";
    const std::string lines = "this line\nand this line\nand this line should be skipped\n";
    const std::string fields = "line skip: 3\n";
    // A NIfTI header's 352 bytes before the samples, in one compressed stream.
    const std::string nifti(352, '\x5c');
    writeBytes(dir / "volume.nii.bz2", test::bzip2Bytes(nifti + data));
    writeBytes(dir / "volume.nii.gz", compress(nifti + data));
    writeBytes(dir / "volume.txt", "# values\n# of a 4x3x2 volume\nXY" + ascii);
    const auto detached = [&](const std::string& encoding, const std::string& extra) {
        return "NRRD0004\n" + basicFields("uint8", "4 3 2", encoding) + extra;
    };
    const std::vector<std::pair<std::string, std::string>> files = {
        // pynrrd's BallBinary30x30x30_gz_lineskip.nrrd: lines after the header.
        {"gz-lines.nrrd",
         nrrd(basicFields("uint8", "4 3 2", "gzip") + fields, lines + compress(data))},
        {"bz2-lines.nrrd",
         nrrd(basicFields("uint8", "4 3 2", "bzip2") + fields, lines + test::bzip2Bytes(data))},
        {"raw-lines.nrrd", nrrd(basicFields("uint8", "4 3 2", "raw") + fields + "byte skip: 2\n",
                                lines + "ab" + data)},
        {"hex-lines.nrrd", nrrd(basicFields("uint8", "4 3 2", "hex") + "lineskip: 1\n",
                                "not hex\n0001" + std::string(42, '0') + " 07\n")},
        // Lines, then bytes of the data file, as teem skips them.
        {"ascii-lines.nhdr",
         detached("ascii", "line skip: 2\nbyte skip: 2\ndata file: volume.txt\n")},
        // pynrrd's BallBinary30x30x30_byteskip_minus_one_nifti.nhdr: the
        // samples are the last bytes of the decompressed data.
        {"gz-end.nhdr", detached("gzip", "byte skip: -1\ndata file: volume.nii.gz\n")},
        {"bz2-end.nhdr", detached("bzip2", "byte skip: -1\ndata file: volume.nii.bz2\n")},
        {"bz2-skip.nhdr", detached("bz2", "byte skip: 352\ndata file: volume.nii.bz2\n")},
    };
    for (const auto& [name, content] : files) {
        writeBytes(dir / name, content);
        expectTwoObjectVoxels(dir / name);
    }
}

TEST(NrrdIO, BrokenTextNamesTheLine) {
    test::TempDir dir;
    // The header's 6 lines and the blank line: the data starts on line 8.
    const std::string fields = basicFields("uint8", "2 2 2", "ascii") + "kinds: ??? ??? ???\n";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {nrrd(fields, "0 1 2\n3 x4 5\n6 7\n"),
         "ascii data, line 9: 'x4' is not a number (sample 5, type uint8)"},
        {nrrd(fields, "0 1 2\n3 4 5\n6 7\n\n 8\n"),
         "data is too long: ascii data has more than the 8 numbers the header says ('8' on line "
         "12)"},
        {nrrd(fields, "0 1 2\n3 4 5\n6 256\n"),
         "ascii data, line 10: '256' is out of range (sample 8, type uint8)"},
        {nrrd(fields, "0 1 2\n3 4 -1 6 7\n"),
         "ascii data, line 9: '-1' is out of range (sample 6, type uint8)"},
        {nrrd(fields, "0 1 2\n3 4 5 6.5 7\n"),
         "ascii data, line 9: '6.5' is not an integer (sample 7, type uint8)"},
        {nrrd(fields, "0 1 2\n3 4 5 6\n\n\n"),
         "data is too short: ascii data has 7 numbers, header says 8"},
        {nrrd(basicFields("uint8", "2 2 2", "hex"), "00 01 02 03\n04 05 06 0g\n"),
         "hex data, line 8: 'g' is not a hex digit"},
        {nrrd(basicFields("uint8", "2 2 2", "hex"), "0001020304050607 0"),
         "data is too long: hex data has more than the 8 bytes the header says (line 7)"},
        {nrrd(basicFields("uint8", "2 2 2", "hex"), "00010203040506 0"),
         "data is too short: hex data ends in the middle of a byte (15 hex digits, an odd "
         "number); header says 8 bytes"},
        {nrrd(basicFields("uint8", "2 2 2", "hex"), "000102030405 0 6"),
         "data is too short: hex data has 7 bytes, header says 8"},
    };
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const fs::path file = dir / ("broken" + std::to_string(i) + ".nrrd");
        writeBytes(file, cases[i].first);
        try {
            readNrrdMask(file);
            ADD_FAILURE() << file << " was accepted";
        } catch (const InputError& error) {
            EXPECT_EQ(std::string(error.what()), file.string() + ": " + cases[i].second);
        }
    }
    // A detached data file's lines are counted in the data file.
    writeBytes(dir / "values.txt", "# comment\n0 1 2 3\n4 5 six 7\n");
    writeBytes(dir / "values.nhdr", "NRRD0004\n" + basicFields("uint8", "2 2 2", "ascii") +
                                        "line skip: 1\ndata file: values.txt\n");
    expectInputError([&] { readNrrdMask(dir / "values.nhdr"); }, "values.nhdr",
                     "ascii data, data file 'values.txt', line 3: 'six' is not a number");
}

TEST(NrrdIO, GeometryFromSpaceFieldsAndSpacings) {
    test::TempDir dir;
    const std::string data(2 * 2 * 2, '\1');
    writeBytes(dir / "space.nrrd",
               nrrd(basicFields("uint8", "2 2 2", "raw",
                                "space: RAS\nspace directions: (0.5,0,0) ( 0, 2 ,0) (0,0,-1.5e-1)\n"
                                "space origin: (1,2,3)\n# a comment\nkinds: domain domain domain\n"
                                "my key:=my value\n"),
                    data));
    const VolumeGeometry geometry = readNrrdMask(dir / "space.nrrd").geometry;
    EXPECT_EQ(geometry.spaceName, "RAS");
    EXPECT_DOUBLE_EQ(geometry.origin[2], 3.0);
    EXPECT_DOUBLE_EQ(geometry.directions[1][1], 2.0);
    EXPECT_DOUBLE_EQ(geometry.directions[2][2], -0.15);
    const auto world = geometry.indexToWorld(1, 1, 1);
    EXPECT_DOUBLE_EQ(world[0], 1.5);
    EXPECT_DOUBLE_EQ(world[1], 4.0);
    EXPECT_DOUBLE_EQ(world[2], 2.85);

    writeBytes(dir / "spacings.nrrd",
               nrrd(basicFields("uint8", "2 2 2", "raw", "spacings: 0.25 nan 4\n"), data));
    const VolumeGeometry spaced = readNrrdMask(dir / "spacings.nrrd").geometry;
    EXPECT_DOUBLE_EQ(spaced.directions[0][0], 0.25);
    EXPECT_DOUBLE_EQ(spaced.directions[1][1], 1.0);  // nan = non-spatial axis -> unit
    EXPECT_DOUBLE_EQ(spaced.directions[2][2], 4.0);
    EXPECT_DOUBLE_EQ(spaced.directions[0][1], 0.0);
    EXPECT_TRUE(spaced.spaceName.empty());

    // Every kind of a spatial or unknown axis is read, in any case, quoted or not.
    writeBytes(dir / "kinds.nrrd",
               nrrd(basicFields("uint8", "2 2 2", "raw", "kinds: space ??? \"Domain\"\n"), data));
    EXPECT_EQ(readNrrdMask(dir / "kinds.nrrd").dims().x, 2);
}

// The per-axis placement ("axis mins", "axis maxs", "centers") that teem's
// nrrdOriginCalculate and nrrdSpacingCalculate read: cell centring (teem's
// default) puts the first sample half a step past the axis's minimum.
TEST(NrrdIO, AxisMinsPlaceAVolumeThatHasNoSpaceFields) {
    test::TempDir dir;
    const std::string data(2 * 4 * 5, '\1');
    const auto geometryOf = [&](const std::string& name, const std::string& fields) {
        writeBytes(dir / name, nrrd(basicFields("uint8", "2 4 5", "raw", fields), data));
        return readNrrdMask(dir / name).geometry;
    };
    const VolumeGeometry cells =
        geometryOf("cells.nrrd", "spacings: 0.5 2 1\naxis mins: 10 -4 nan\n");
    EXPECT_DOUBLE_EQ(cells.origin[0], 10.25);
    EXPECT_DOUBLE_EQ(cells.origin[1], -3.0);
    EXPECT_DOUBLE_EQ(cells.origin[2], 0.0);  // nan: no minimum on that axis
    EXPECT_DOUBLE_EQ(cells.directions[1][1], 2.0);

    const VolumeGeometry nodes = geometryOf(
        "nodes.nrrd", "spacings: 0.5 2 1\naxismins: 10 -4 7\ncenterings: cell node \"???\"\n");
    EXPECT_DOUBLE_EQ(nodes.origin[0], 10.25);
    EXPECT_DOUBLE_EQ(nodes.origin[1], -4.0);
    EXPECT_DOUBLE_EQ(nodes.origin[2], 7.5);

    // Without spacings, the step is the range over the samples (cell) or
    // over the intervals between them (node).
    const VolumeGeometry ranges =
        geometryOf("ranges.nrrd", "axis mins: 0 0 1\naxis maxs: 1 2 3\ncenters: cell Node none\n");
    EXPECT_DOUBLE_EQ(ranges.directions[0][0], 0.5);
    EXPECT_DOUBLE_EQ(ranges.directions[1][1], 2.0 / 3.0);
    EXPECT_DOUBLE_EQ(ranges.directions[2][2], 0.4);
    EXPECT_DOUBLE_EQ(ranges.origin[0], 0.25);
    EXPECT_DOUBLE_EQ(ranges.origin[1], 0.0);
    EXPECT_DOUBLE_EQ(ranges.origin[2], 1.2);
    const auto last = ranges.indexToWorld(1, 3, 4);
    EXPECT_DOUBLE_EQ(last[0], 0.75);  // half a step inside the cell range's end
    EXPECT_DOUBLE_EQ(last[1], 2.0);   // on the node range's end
    EXPECT_NEAR(last[2], 2.8, 1e-12);

    // "space origin" and "space directions" replace the per-axis fields.
    const VolumeGeometry spaced =
        geometryOf("spaced.nrrd", "space origin: (1,2,3)\nspacings: 1 1 1\naxis mins: 10 10 10\n");
    EXPECT_DOUBLE_EQ(spaced.origin[0], 1.0);
    const VolumeGeometry directed =
        geometryOf("directed.nrrd",
                   "space: RAS\nspace directions: (1,0,0) (0,1,0) (0,0,1)\naxis mins: 10 10 10\n");
    EXPECT_DOUBLE_EQ(directed.origin[0], 0.0);

    // A 4-D header's dropped axis has its own entry in every per-axis field.
    writeBytes(dir / "four.nrrd", nrrd("type: uint8\ndimension: 4\nsizes: 1 2 4 5\nencoding: raw\n"
                                       "kinds: scalar domain domain domain\nspacings: nan 0.5 2 1\n"
                                       "axis mins: nan 10 -4 6\ncenters: none cell node node\n",
                                       data));
    const VolumeGeometry four = readNrrdMask(dir / "four.nrrd").geometry;
    EXPECT_DOUBLE_EQ(four.origin[0], 10.25);
    EXPECT_DOUBLE_EQ(four.origin[1], -4.0);
    EXPECT_DOUBLE_EQ(four.origin[2], 6.0);

    // Written out, the placement is kept as space origin and directions.
    LabelVolume labels(Dims{2, 4, 5}, 1);
    labels.geometry = ranges;
    writeNrrdLabels(dir / "labels.nrrd", labels);
    expectSameGeometry(readNrrdLabels(dir / "labels.nrrd").geometry, ranges);

    writeBytes(dir / "count.nrrd",
               nrrd(basicFields("uint8", "2 4 5", "raw", "axis mins: 0 0\n"), data));
    expectInputError([&] { readNrrdMask(dir / "count.nrrd"); }, "count.nrrd",
                     "axis mins lists 2 values for a dimension of 3");
    writeBytes(
        dir / "centre.nrrd",
        nrrd(basicFields("uint8", "2 4 5", "raw", "axis mins: 0 0 0\ncenters: cell middle cell\n"),
             data));
    expectInputError([&] { readNrrdMask(dir / "centre.nrrd"); }, "centre.nrrd",
                     "centers: unknown centering 'middle' (expected cell, node, ??? or none)");
    // Centers are read only to place a volume by its axis mins.
    writeBytes(dir / "unused.nrrd",
               nrrd(basicFields("uint8", "2 4 5", "raw", "centers: cell middle\n"), data));
    EXPECT_EQ(readNrrdMask(dir / "unused.nrrd").dims().z, 5);
}

TEST(NrrdIO, LabelsOutputReproducesInputGeometry) {
    test::TempDir dir;
    const std::string data(3 * 2 * 2, '\1');
    writeBytes(dir / "input.nrrd", nrrd(basicFields("uint8", "3 2 2", "raw",
                                                    "space: left-posterior-superior\n"
                                                    "space directions: (0.1,0.2,0) (0,0.3,0.4) "
                                                    "(0.7,0,0.9)\nspace origin: (-1,-2,-3)\n"),
                                        data));
    const MaskVolume input = readNrrdMask(dir / "input.nrrd");
    LabelVolume labels(input.dims(), 1);
    labels.geometry = input.geometry;
    writeNrrdLabels(dir / "labels.nrrd", labels);
    expectSameGeometry(readNrrdLabels(dir / "labels.nrrd").geometry, input.geometry);
}

TEST(NrrdIO, MemoryReaders) {
    std::string data(2 * 2 * 2, '\0');
    data[7] = 1;
    // Windows line ends in the header are accepted.
    const std::string bytes =
        "NRRD0004\r\ntype: uint8\r\ndimension: 3\r\nsizes: 2 2 2\r\nencoding: raw\r\n\r\n" + data;
    const auto* begin = reinterpret_cast<const std::uint8_t*>(bytes.data());
    EXPECT_EQ(readNrrdMaskFromMemory("buffer", begin, bytes.size())(1, 1, 1), 1);
    EXPECT_EQ(readNrrdLabelsFromMemory("buffer", begin, bytes.size())(1, 1, 1), 1);

    const std::string detached =
        "NRRD0004\n" + basicFields("uint8", "2 2 2", "raw") + "data file: x.raw\n";
    expectInputError(
        [&] {
            readNrrdMaskFromMemory("in-memory.nhdr",
                                   reinterpret_cast<const std::uint8_t*>(detached.data()),
                                   detached.size());
        },
        "in-memory.nhdr", "memory");
}

TEST(NrrdIO, LabelsRejectNonIntegerLabelTypes) {
    test::TempDir dir;
    writeBytes(dir / "float.nrrd", nrrd(basicFields("float", "1 1 1", "raw", "endian: little\n"),
                                        std::string(4, '\0')));
    expectInputError([&] { readNrrdLabels(dir / "float.nrrd"); }, "float.nrrd", "uint8 or uint16");
}

// ---------------------------------------------------------------------------
// 4-D headers with a size-1 axis, and data in several files: each form of the
// same volume reads as the one 3-D file does.
// ---------------------------------------------------------------------------

/// 5 x 4 x 6 uint16 labels, every value distinct in both bytes, as raw
/// little-endian samples (x fastest).
std::string sixSlices() {
    std::string data;
    for (int i = 0; i < 5 * 4 * 6; ++i) {
        const std::uint16_t value = std::uint16_t(i % 7 == 0 ? 0 : 300 * i + 1);
        data += char(value & 0xff);
        data += char(value >> 8);
    }
    return data;
}
constexpr std::size_t kSliceBytes = 5 * 4 * 2;

/// The geometry every form of sixSlices() gives.
const std::string kSixSlicesGeometry = "space: left-posterior-superior\nspace origin: (1.5,-2,3)\n";
const std::string kDirections = "(0.5,0,0) (0,0.75,0) (0,0,1.25)";

std::string uint16Fields(const std::string& dimension, const std::string& sizes,
                         const std::string& encoding = "raw") {
    return "type: uint16\nendian: little\ndimension: " + dimension + "\nsizes: " + sizes +
           "\nencoding: " + encoding + "\n" + kSixSlicesGeometry;
}

/// The reference: sixSlices() as one attached 3-D file.
LabelVolume sixSlicesVolume(const fs::path& dir) {
    writeBytes(
        dir / "reference.nrrd",
        nrrd(uint16Fields("3", "5 4 6") + "space directions: " + kDirections + "\n", sixSlices()));
    return readNrrdLabels(dir / "reference.nrrd");
}

/// `file` reads as `reference`: dims, geometry and every voxel.
void expectSameVolume(const fs::path& file, const LabelVolume& reference) {
    SCOPED_TRACE(file.filename().string());
    LabelVolume volume;
    try {
        volume = readNrrdLabels(file);
    } catch (const InputError& error) {
        ADD_FAILURE() << error.what();
        return;
    }
    ASSERT_EQ(volume.dims(), reference.dims());
    expectSameGeometry(volume.geometry, reference.geometry);
    EXPECT_TRUE(std::equal(volume.data(), volume.data() + volume.size(), reference.data()));
    // The mask reader takes the same path.
    const MaskVolume mask = readNrrdMask(file);
    for (std::size_t i = 0; i < mask.size(); ++i)
        ASSERT_EQ(mask[i], reference[i] != 0 ? 1 : 0) << "voxel " << i;
}

TEST(NrrdIO, FourDimensionsWithASizeOneAxisReadAsTheThreeOthers) {
    test::TempDir dir;
    const LabelVolume reference = sixSlicesVolume(dir.path());
    ASSERT_EQ(reference.dims(), (Dims{5, 4, 6}));
    const std::string data = sixSlices();
    const std::vector<std::pair<std::string, std::string>> forms = {
        // The size-1 axis first (a scalar or one-component vector axis), as
        // ITK and Slicer write it; its direction is "none".
        {"first.nrrd", uint16Fields("4", "1 5 4 6") +
                           "kinds: scalar domain domain domain\nspace directions: none " +
                           kDirections + "\n"},
        {"first-vector.nrrd", uint16Fields("4", "1 5 4 6") +
                                  "kinds: vector space space space\nspace directions: none " +
                                  kDirections + "\n"},
        // Last, without kinds: the axis of size 1 that has no direction.
        {"last.nrrd",
         uint16Fields("4", "5 4 6 1") + "space directions: " + kDirections + " none\n"},
        {"last-list.nrrd",
         uint16Fields("4", "5 4 6 1") +
             "kinds: domain domain domain list\nspace directions: " + kDirections + " none\n"},
        // Neither kinds nor directions: the one axis of size 1 (spacings
        // list four values, NaN for it).
        {"spacings.nrrd",
         "type: uint16\nendian: little\ndimension: 4\nsizes: 5 4 1 6\n"
         "encoding: raw\nspace: left-posterior-superior\n"
         "space origin: (1.5,-2,3)\nspacings: 0.5 0.75 nan 1.25\n"},
        {"unknown-kind.nrrd", uint16Fields("4", "5 1 4 6") +
                                  "kinds: domain ??? domain domain\nspacings: 0.5 nan 0.75 1.25\n"},
    };
    for (const auto& [name, fields] : forms) {
        writeBytes(dir / name, nrrd(fields, data));
        expectSameVolume(dir / name, reference);
    }
}

TEST(NrrdIO, FourDimensionsRefuseAnAxisOfMoreThanOneSample) {
    test::TempDir dir;
    const std::string data = sixSlices();
    const struct {
        const char* name;
        std::string fields;
        const char* problem;
    } cases[] = {
        {"rgb.nrrd", uint16Fields("4", "3 5 4 2") + "kinds: RGB-color domain domain domain\n",
         "axis 0 (kind 'RGB-color') has size 3: the file holds several 3-D volumes (a time "
         "series, or the components of a colour or vector volume), not one; keep one with 'unu "
         "slice -a 0 -p 0' (or take one component) and segment that"},
        {"series.nrrd", uint16Fields("4", "5 4 3 2") + "kinds: domain domain domain time\n",
         "axis 3 (kind 'time') has size 2"},
        {"none.nrrd", uint16Fields("4", "5 4 3 2") + "space directions: " + kDirections + " none\n",
         "axis 3 has size 2: the file holds several 3-D volumes"},
        {"no-size-1.nrrd", uint16Fields("4", "5 4 3 2"),
         "dimension 4 with no axis of size 1 (sizes 5 4 3 2)"},
        {"two-size-1.nrrd", uint16Fields("4", "1 5 24 1"),
         "axes 0 and 3 have size 1, and neither 'kinds' nor 'space directions' says which is not "
         "spatial"},
        {"two-kinds.nrrd", uint16Fields("4", "1 5 24 1") + "kinds: scalar domain domain time\n",
         "axes 0 and 3 are of kinds that are not spatial"},
        {"all-spatial.nrrd", uint16Fields("4", "1 5 4 6") + "kinds: domain domain domain domain\n",
         "kinds gives every axis of size 1 a spatial kind"},
        {"spatial-none.nrrd",
         uint16Fields("4", "1 5 4 6") + "kinds: scalar domain domain domain\n" +
             "space directions: (1,0,0) none (0,1,0) (0,0,1)\n",
         "space directions: axis 1 is 'none', but only axis 0 is not spatial"},
        {"dimension-5.nrrd", uint16Fields("5", "1 5 4 6 1"), "dimension 5 is not supported"},
        {"dimension-2.nrrd", uint16Fields("2", "20 24"), "dimension 2 is not supported"},
    };
    for (const auto& c : cases) {
        writeBytes(dir / c.name, nrrd(c.fields, data));
        expectInputError([&] { readNrrdMask(dir / c.name); }, c.name, c.problem);
    }
}

/// A detached header over sixSlices(): `dataFile` is the "data file" field
/// and what follows it.
void writeDetached(const fs::path& file, const std::string& dataFile,
                   const std::string& encoding = "raw", const std::string& extra = "") {
    writeBytes(file, "NRRD0004\n" + uint16Fields("3", "5 4 6", encoding) + "space directions: " +
                         kDirections + "\n" + extra + "data file: " + dataFile);
}

TEST(NrrdIO, DataInSeveralFilesReadsAsOneFile) {
    test::TempDir dir;
    const LabelVolume reference = sixSlicesVolume(dir.path());
    const std::string data = sixSlices();
    const auto slice = [&](int z) {
        return data.substr(std::size_t(z) * kSliceBytes, kSliceBytes);
    };
    fs::create_directories(dir / "slices");
    std::string list;
    for (int z = 0; z < 6; ++z) {
        const std::string name = "slice" + std::to_string(z) + ".raw";
        writeBytes(dir / "slices" / name, slice(z));
        list += "slices/" + name + "\n";
        // Numbered down: file 005 holds slice 0.
        char down[32];
        std::snprintf(down, sizeof(down), "down%03d.raw", 5 - z);
        writeBytes(dir / down, slice(z));
        char up[32];
        std::snprintf(up, sizeof(up), "up-%02d.raw", 10 + 2 * z);
        writeBytes(dir / up, slice(z));
        writeBytes(dir / ("z" + std::to_string(z) + ".raw.gz"), compress("ab" + slice(z)));
        writeBytes(
            dir / ("z" + std::to_string(z) + ".txt"), "# slice\n" + [&] {
                std::string numbers;
                for (std::size_t i = 0; i < kSliceBytes; i += 2)
                    numbers += std::to_string(std::uint8_t(slice(z)[i]) +
                                              256 * std::uint8_t(slice(z)[i + 1])) +
                               " ";
                return numbers + "\n";
            }());
    }
    writeBytes(dir / "half0.raw", data.substr(0, 3 * kSliceBytes));
    writeBytes(dir / "half1.raw", data.substr(3 * kSliceBytes));

    writeDetached(dir / "list.nhdr", "LIST\n" + list);
    writeDetached(dir / "list-2d.nhdr", "LIST 2\n" + list + "\n");
    writeDetached(dir / "up.nhdr", "up-%02d.raw 10 20 2\n");
    writeDetached(dir / "down.nhdr", "down%03d.raw 5 0 -1\n");
    writeDetached(dir / "halves.nhdr", "LIST 3\nhalf0.raw\nhalf1.raw\n");
    writeDetached(dir / "halves-pattern.nhdr", "half%d.raw 0 1 1 3\n");
    // Skips apply to each file; gzip's byte skip to its decompressed data.
    writeDetached(dir / "gzip.nhdr", "z%d.raw.gz 0 5 1\n", "gzip", "byte skip: 2\n");
    writeDetached(dir / "ascii.nhdr", "z%d.txt 0 5 1\n", "ascii", "line skip: 1\n");
    for (const char* name : {"list.nhdr", "list-2d.nhdr", "up.nhdr", "down.nhdr", "halves.nhdr",
                             "halves-pattern.nhdr", "gzip.nhdr", "ascii.nhdr"})
        expectSameVolume(dir / name, reference);

    // Every file is an input of the header: outputs are checked against them.
    const std::vector<fs::path> inputs = volumeInputFiles(dir / "down.nhdr");
    ASSERT_EQ(inputs.size(), 7u);
    EXPECT_EQ(inputs[1], dir / "down005.raw");
    EXPECT_EQ(inputs[6], dir / "down000.raw");
    EXPECT_EQ(volumeInputFiles(dir / "list.nhdr").back(), dir / "slices" / "slice5.raw");
}

TEST(NrrdIO, AListPastTheFirstMebibyteIsListedWhole) {
    // Outputs are checked against the data files before the run reads them,
    // from the header's first MiB: a list that goes on past it was cut.
    test::TempDir dir;
    const std::string folder(250, 'd');
    fs::create_directories(dir / folder);
    std::string list = "LIST 1\n";
    for (int row = 0; row < 64 * 64; ++row) {
        char name[32];
        std::snprintf(name, sizeof(name), "/r%04d.raw", row);
        writeBytes(dir / (folder + name), std::string(64, char(row % 3 == 0)));
        list += folder + name + "\n";
    }
    writeBytes(dir / "rows.nhdr",
               "NRRD0004\n" + basicFields("uint8", "64 64 64", "raw") + "data file: " + list);
    ASSERT_GT(fileBytes(dir / "rows.nhdr").size(), std::size_t(1) << 20);
    const std::vector<fs::path> inputs = volumeInputFiles(dir / "rows.nhdr");
    ASSERT_EQ(inputs.size(), 1u + 64 * 64);
    EXPECT_EQ(inputs.back(), dir / (folder + "/r4095.raw"));
    const MaskVolume mask = readNrrdMask(dir / "rows.nhdr");
    EXPECT_EQ(countNonzero(mask), std::size_t(64 * ((64 * 64 + 2) / 3)));
    EXPECT_EQ(mask(5, 3, 0), 1);
    EXPECT_EQ(mask(5, 4, 0), 0);
}

TEST(NrrdIO, AListLongerThanTheLongestHeaderIsRefusedAsTheListingReadsIt) {
    // The output checks read a list from the header's first
    // kMaxNrrdHeaderBytes; the reader refuses a longer header, so no listed
    // file goes unchecked. A million names of 71 bytes: over the limit.
    test::TempDir dir;
    std::string header =
        "NRRD0004\n" + basicFields("uint8", "2 1000 1000", "raw") + "data file: LIST 1\n";
    const std::string name(70, 'n');
    header.reserve(header.size() + 1000000 * (name.size() + 1));
    for (int row = 0; row < 1000000; ++row) header += name + "\n";
    ASSERT_GT(header.size(), kMaxNrrdHeaderBytes);
    writeBytes(dir / "long.nhdr", header);
    EXPECT_EQ(volumeInputFiles(dir / "long.nhdr").size(), 1u);
    expectInputError([&] { readNrrdMask(dir / "long.nhdr"); }, "long.nhdr",
                     "at most " + std::to_string(kMaxNrrdHeaderBytes - 1) + " are read");
}

TEST(NrrdIO, DataInSeveralFilesRefusesWhatDoesNotAddUp) {
    test::TempDir dir;
    const std::string data = sixSlices();
    for (int z = 0; z < 6; ++z)
        writeBytes(dir / ("s" + std::to_string(z) + ".raw"),
                   data.substr(std::size_t(z) * kSliceBytes, kSliceBytes));
    writeBytes(dir / "short.raw", data.substr(0, kSliceBytes - 2));
    writeBytes(dir / "long.raw", data.substr(0, kSliceBytes + 1));
    std::string five;
    for (int z = 0; z < 5; ++z) five += "s" + std::to_string(z) + ".raw\n";
    const struct {
        const char* name;
        std::string dataFile;
        const char* problem;
    } cases[] = {
        {"five.nhdr", "LIST\n" + five,
         "data file 'LIST' names 5 files, but sizes 5 4 6 are 6 pieces of 2 dimensions, one a "
         "file"},
        {"seven.nhdr", "LIST\n" + five + "s5.raw\ns0.raw\n", "names 7 files"},
        {"empty-list.nhdr", "LIST\n", "no file names follow it"},
        {"missing.nhdr", "LIST\n" + five + "absent.raw\n", "data file 'absent.raw': no such file"},
        {"short.nhdr", "LIST\n" + five + "short.raw\n",
         "data file 'short.raw': data is too short: 38 bytes, header says 40"},
        {"long.nhdr", "LIST\n" + five + "long.raw\n",
         "data file 'long.raw': data is too long: 41 bytes, header says 40"},
        {"uneven.nhdr", "LIST 3\ns0.raw\ns1.raw\ns2.raw\ns3.raw\n",
         "names 4 files, but the 6 slices of the slowest axis do not split into as many equal "
         "runs"},
        {"subdim-4.nhdr", "LIST 4\ns0.raw\n", "the dimension of each file's data, 4, is not"},
        {"pattern-few.nhdr", "s%d.raw 0 4 1\n", "names 5 files"},
        {"pattern-two.nhdr", "s%d%d.raw 0 5 1\n",
         "data file pattern 's%d%d.raw 0 5 1' has 2 conversions; it must have exactly one "
         "integer conversion (such as %03d)"},
        {"pattern-none.nhdr", "s%%.raw 0 5 1\n", "has 0 conversions"},
        {"pattern-s.nhdr", "s%s.raw 0 5 1\n",
         "has '%s', which is not an integer conversion (such as %d or %03d)"},
        {"pattern-n.nhdr", "s%n%d.raw 0 5 1\n", "'%n', which is not an integer conversion"},
        {"pattern-star.nhdr", "s%*d.raw 0 5 1\n", "'%*', which is not an integer conversion"},
        {"pattern-long.nhdr", "s%ld.raw 0 5 1\n", "'%l', which is not an integer conversion"},
        {"pattern-wide.nhdr", "s%9999d.raw 0 5 1\n", "more than 3 digits"},
        {"pattern-step-0.nhdr", "s%d.raw 0 5 0\n", "the step is 0"},
        {"pattern-backwards.nhdr", "s%d.raw 5 0 1\n", "names no file"},
        {"pattern-no-step.nhdr", "s%d.raw 0 5\n", "a pattern takes its first and last number"},
        {"pattern-missing.nhdr", "s%d.raw 1 6 1\n", "data file 's6.raw': no such file"},
        {"pattern-negative-x.nhdr", "s%x.raw -1 4 1\n", "cannot be written with %x"},
        {"nul.nhdr", "LIST\n" + five + "s5.raw" + std::string(1, '\0') + "x\n",
         "the name holds a NUL byte"},
        {"directory.nhdr", "LIST\n" + five + ".\n", "data file '.': is a directory"},
    };
    for (const auto& c : cases) {
        writeDetached(dir / c.name, c.dataFile);
        expectInputError([&] { readNrrdMask(dir / c.name); }, c.name, c.problem);
    }
    // Six good files, from memory: a detached header cannot be read there.
    const std::string header =
        "NRRD0004\n" + uint16Fields("3", "5 4 6") + "data file: s%d.raw 0 5 1\n";
    expectInputError(
        [&] {
            readNrrdMaskFromMemory("mem.nhdr", reinterpret_cast<const std::uint8_t*>(header.data()),
                                   header.size());
        },
        "mem.nhdr", "cannot be read from memory");
}

TEST(NrrdIO, MalformedFilesGiveOneLineErrorsNamingFileAndProblem) {
    test::TempDir dir;
    const std::string raw24(2 * 3 * 4, '\0');
    const std::string ok = basicFields("uint8", "2 3 4", "raw");
    std::string corrupt = compress(raw24);
    corrupt[corrupt.size() / 2] = char(corrupt[corrupt.size() / 2] ^ 0x55);
    corrupt[10] = char(0xff);
    const std::string gzipped = compress(raw24);
    const std::string bzipped = test::bzip2Bytes(raw24);
    std::string bzipCorrupt = bzipped;
    for (std::size_t i = 12; i < 20 && i < bzipCorrupt.size(); ++i) bzipCorrupt[i] = '\xa5';
    const std::string bz = basicFields("uint8", "2 3 4", "bzip2");
    const std::string ascii = basicFields("uint8", "2 3 4", "ascii");
    const std::string hex = basicFields("uint8", "2 3 4", "hex");
    struct Case {
        const char* name;
        std::string content;
        const char* keyword;
    };
    const std::vector<Case> cases = {
        {"empty", "", "empty"},
        {"wrong-magic", "P5\n2 3\n255\n", "magic"},
        {"version", "NRRD0009\n" + ok + "\n" + raw24, "version"},
        {"no-dimension", nrrd("type: uint8\nsizes: 2 3 4\nencoding: raw\n", raw24), "dimension"},
        {"no-type", nrrd("dimension: 3\nsizes: 2 3 4\nencoding: raw\n", raw24), "'type'"},
        {"no-sizes", nrrd("type: uint8\ndimension: 3\nencoding: raw\n", raw24), "'sizes'"},
        {"no-encoding", nrrd("type: uint8\ndimension: 3\nsizes: 2 3 4\n", raw24), "'encoding'"},
        {"dimension-2",
         nrrd("type: uint8\ndimension: 2\nsizes: 2 3\nencoding: raw\n", raw24.substr(0, 6)),
         "dimension 2"},
        {"dimension-4", nrrd("type: uint8\ndimension: 4\nsizes: 2 3 4 2\nencoding: raw\n", raw24),
         "dimension 4 with no axis of size 1"},
        {"sizes-count", nrrd("type: uint8\ndimension: 3\nsizes: 2 3\nencoding: raw\n", raw24),
         "sizes"},
        {"negative-size", nrrd(basicFields("uint8", "2 -3 4", "raw"), raw24), "not positive"},
        {"zero-size", nrrd(basicFields("uint8", "2 0 4", "raw"), raw24), "not positive"},
        {"huge-size", nrrd(basicFields("uint8", "2 100000 4", "raw"), raw24), "limit"},
        {"overflow-size", nrrd(basicFields("uint8", "2 99999999999999999999999 4", "raw"), raw24),
         "too large"},
        {"too-many-voxels", nrrd(basicFields("uint8", "8192 8192 8192", "raw"), raw24), "limit"},
        {"fractional-size", nrrd(basicFields("uint8", "2 3.5 4", "raw"), raw24), "not an integer"},
        {"text-size", nrrd(basicFields("uint8", "2 three 4", "raw"), raw24), "not an integer"},
        {"unsupported-type", nrrd(basicFields("block", "2 3 4", "raw"), raw24), "unsupported type"},
        {"unsupported-encoding", nrrd(basicFields("uint8", "2 3 4", "zrl"), raw24),
         "unsupported encoding 'zrl' (supported: raw, ascii, hex, gzip, bzip2)"},
        {"missing-endian", nrrd(basicFields("uint16", "2 3 4", "raw"), raw24 + raw24), "endian"},
        {"bad-endian",
         nrrd(basicFields("uint16", "2 3 4", "raw", "endian: middle\n"), raw24 + raw24), "endian"},
        {"byte-skip", nrrd(ok + "byte skip: -3\n", raw24), "byte skip '-3' is invalid"},
        {"raw-short", nrrd(ok, raw24.substr(0, 23)), "too short"},
        {"raw-long", nrrd(ok, raw24 + "x"), "too long"},
        {"raw-missing", nrrd(ok, ""), "too short"},
        {"gzip-short", nrrd(basicFields("uint8", "2 3 4", "gzip"), compress(raw24.substr(0, 20))),
         "too short"},
        {"gzip-long", nrrd(basicFields("uint8", "2 3 4", "gzip"), compress(raw24 + "abc")),
         "too long"},
        {"gzip-truncated",
         nrrd(basicFields("uint8", "2 3 4", "gzip"), gzipped.substr(0, gzipped.size() - 9)),
         "too short"},
        {"gzip-trailing", nrrd(basicFields("uint8", "2 3 4", "gzip"), gzipped + "junk"),
         "too long"},
        {"gzip-corrupt", nrrd(basicFields("uint8", "2 3 4", "gzip"), corrupt), "corrupt"},
        {"gzip-not-gzip", nrrd(basicFields("uint8", "2 3 4", "gzip"), "this is not compressed"),
         "corrupt"},
        {"gzip-implausible", nrrd(basicFields("uint8", "4000 4000 200", "gzip"), gzipped),
         "cannot hold"},
        {"bzip2-corrupt", nrrd(bz, bzipCorrupt), "corrupt bzip2 data"},
        {"bzip2-not-bzip2", nrrd(bz, "this is not compressed"),
         "corrupt bzip2 data: no bzip2 signature 'BZh'"},
        {"bzip2-truncated", nrrd(bz, bzipped.substr(0, bzipped.size() - 6)), "too short"},
        {"bzip2-short", nrrd(bz, test::bzip2Bytes(raw24.substr(0, 20))),
         "data is too short: bzip2 data decompresses to 20 bytes, header says 24"},
        {"bzip2-long", nrrd(bz, test::bzip2Bytes(raw24 + "abc")),
         "data is too long: bzip2 data decompresses to more than the 24 bytes"},
        {"bzip2-trailing", nrrd(bz, bzipped + "junk"),
         "data is too long: 4 bytes after the end of the bzip2 stream"},
        {"bzip2-implausible", nrrd(basicFields("uint8", "8000 8000 60", "bzip2"), bzipped),
         "cannot hold"},
        {"bzip2-empty", nrrd(bz, ""), "data is too short: bzip2 data is truncated after 0"},
        // Every sample decodes, the stream's end and checksum are cut off.
        {"gzip-no-trailer",
         nrrd(basicFields("uint8", "2 3 4", "gzip"), gzipped.substr(0, gzipped.size() - 8)),
         "data is too short: the gzip stream is cut off after 24 bytes, before its end and "
         "checksum"},
        {"bzip2-no-end", nrrd(bz, bzipped.substr(0, bzipped.size() - 4)),
         "data is too short: the bzip2 stream is cut off after 24 bytes, before its end and "
         "checksum"},
        {"ascii-implausible", nrrd(basicFields("uint8", "4000 4000 200", "ascii"), "1 2 3"),
         "data is too short: ascii data has 3 numbers, header says 3200000000"},
        {"ascii-few", nrrd(ascii, "1 2 3 4" + std::string(40, ' ')),
         "ascii data has 4 numbers, header says 24"},
        {"ascii-word",
         nrrd(ascii,
              [] {
                  std::string numbers;
                  for (int i = 0; i < 23; ++i) numbers += "1 ";
                  return numbers + "one";
              }()),
         "'one' is not a number (sample 24, type uint8)"},
        {"ascii-end-skip", nrrd(ascii + "byte skip: -1\n", std::string(48, '1')),
         "byte skip -1 (the data's last bytes) is not supported for ascii data"},
        {"hex-implausible", nrrd(hex, std::string(47, 'a')), "47 bytes of hex data cannot hold"},
        {"hex-odd", nrrd(hex, std::string(49, 'a')), "too long"},
        {"hex-sign", nrrd(hex, "-" + std::string(48, 'a')), "'-' is not a hex digit"},
        {"line-skip-negative", nrrd(ok + "line skip: -1\n", raw24),
         "line skip '-1' is invalid (it is at least 0)"},
        {"line-skip-past", nrrd(ok + "line skip: 3\n", "one\ntwo\n" + raw24),
         "data is too short: line skip 3 passes the end of the data after 2 lines"},
        {"gzip-end-short",
         nrrd(basicFields("uint8", "2 3 4", "gzip") + "byte skip: -1\n", compress(raw24.substr(1))),
         "data is too short: gzip data decompresses to 23 bytes, header says at least 24"},
        {"gzip-end-long",
         nrrd(basicFields("uint8", "2 3 4", "gzip") + "byte skip: -1\n",
              compress(std::string((1 << 20) + 25, 'x'))),
         "with byte skip -1 the bytes before the samples are at most as many as the samples' "
         "(or 1 MiB)"},
        {"no-blank-line", "NRRD0004\n" + ok, "blank line"},
        {"duplicate-field", nrrd(ok + "type: uint8\n", raw24), "twice"},
        {"malformed-line", nrrd(ok + "this line has no colon\n", raw24), "malformed"},
        {"direction-none", nrrd(ok + "space directions: none (1,0,0) (0,1,0)\n", raw24), "none"},
        {"direction-2d", nrrd(ok + "space directions: (1,0) (0,1) (1,1)\n", raw24), "components"},
        {"direction-count", nrrd(ok + "space directions: (1,0,0) (0,1,0)\n", raw24),
         "space directions"},
        {"direction-text", nrrd(ok + "space directions: (1,a,0) (0,1,0) (0,0,1)\n", raw24),
         "not a number"},
        {"origin-infinite", nrrd(ok + "space origin: (inf,0,0)\n", raw24), "finite"},
        {"unknown-space", nrrd(ok + "space: upside-down\n", raw24), "unknown space"},
        {"time-space", nrrd(ok + "space: RAST\n", raw24), "only 3D"},
        {"space-dimension", nrrd(ok + "space dimension: 2\n", raw24), "space dimension"},
        // A colour or vector axis made a two-dimensional image a slab of voxels.
        {"kinds-colour", nrrd(ok + "kinds: RGB-color domain domain\n", raw24),
         "axis 0 is of kind 'RGB-color', not a spatial axis"},
        {"kinds-time", nrrd(ok + "kinds: domain domain time\n", raw24), "axis 2 is of kind"},
        {"kinds-vector", nrrd(ok + "kinds: domain 3-vector domain\n", raw24), "axis 1"},
        {"kinds-count", nrrd(ok + "kinds: domain domain\n", raw24), "kinds lists 2 values"},
        {"data-file-list", "NRRD0004\n" + ok + "data file: LIST\na.raw\n",
         "data file 'LIST' names 1 file, but sizes 2 3 4 are 4 pieces"},
        {"data-file-missing", "NRRD0004\n" + ok + "data file: absent.raw\n", "no such file"},
    };
    for (const auto& c : cases) {
        const std::string fileName = std::string(c.name) + ".nrrd";
        writeBytes(dir / fileName, c.content);
        expectInputError([&] { readNrrdMask(dir / fileName); }, fileName, c.keyword);
        // The memory reader reports the same problems (detached data aside).
        if (std::string(c.name).rfind("data-file-missing", 0) == 0) continue;
        expectInputError(
            [&] {
                readNrrdMaskFromMemory(fileName,
                                       reinterpret_cast<const std::uint8_t*>(c.content.data()),
                                       c.content.size());
            },
            fileName, c.keyword);
    }
}

TEST(NrrdIO, GeometryThatCannotBeRepresentedIsRefused) {
    test::TempDir dir;
    const std::string raw24(2 * 3 * 4, '\1');
    const std::string ok = basicFields("uint8", "2 3 4", "raw");
    struct Case {
        const char* name;
        std::string fields;
        const char* problem;
    };
    const std::vector<Case> cases = {
        {"far", ok + "space origin: (1e15,0,0)\n",
         "world coordinates reach 1e+15, where the voxel step along axis 0 (1) is below 2^-40 of "
         "them: neighbouring voxels would get nearly the same world coordinates"},
        {"zero-spacing", ok + "spacings: 1 0 1\n",
         "the voxel step along axis 1 is zero: the voxels have no volume"},
        {"subnormal-spacing", ok + "spacings: 1 1 5e-324\n",
         "the voxel step along axis 2 (4.94066e-324) is a subnormal number: the voxels have no "
         "usable size"},
        {"parallel", ok + "space directions: (1,0,0) (2,0,0) (0,0,1)\n",
         "the voxel steps are parallel or nearly so: the voxels have no volume"},
        {"overflow", ok + "space origin: (1.7e308,0,0)\nspacings: 1e308 1 1\n",
         "world coordinates overflow: voxel (1, 0, 0) lies at a non-finite position"},
    };
    for (const auto& c : cases) {
        const std::string fileName = std::string(c.name) + ".nrrd";
        writeBytes(dir / fileName, nrrd(c.fields, raw24));
        try {
            readNrrdMask(dir / fileName);
            ADD_FAILURE() << fileName << " was accepted";
        } catch (const InputError& error) {
            EXPECT_EQ(std::string(error.what()), (dir / fileName).string() + ": " + c.problem);
        }
    }
    // 1 um voxels a million units from the origin keep distinct positions.
    writeBytes(dir / "micrometres.nrrd",
               nrrd(ok + "space origin: (1e6,-1e6,0)\nspacings: 1e-6 1e-6 1e-6\n", raw24));
    EXPECT_DOUBLE_EQ(readNrrdMask(dir / "micrometres.nrrd").geometry.origin[0], 1e6);
}

TEST(NrrdIO, FileSystemErrors) {
    test::TempDir dir;
    expectInputError([&] { readNrrdMask(dir / "absent.nrrd"); }, "absent.nrrd", "no such file");
    fs::create_directories(dir / "folder.nrrd");
    expectInputError([&] { readNrrdMask(dir / "folder.nrrd"); }, "folder.nrrd", "is a directory");
}

TEST(NrrdIO, WriterFailureIsOutputError) {
    test::TempDir dir;
    const LabelVolume labels = makeLabels();
    EXPECT_THROW(writeNrrdLabels(dir / "no" / "such" / "dir" / "labels.nrrd", labels), OutputError);
}
