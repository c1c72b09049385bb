// Robustness of the CLI end (issue 5): bad input of every format costs exit
// code 2 and one line naming the file, and leaves no output; limits, usage
// errors, interrupted runs and existing results behave as documented in
// docs/robustness.md. The parsers themselves are unit-tested in tests/io and
// fuzzed in tests/fuzz; here the built `skelseg` runs as a child process.
// OpenVDB inputs: TestRobustnessVdb.cpp. Degenerate shapes: SlowRobustness.cpp.
#include <sched.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <ostream>
#include <thread>

#include <nlohmann/json.hpp>

#include "engine/BatchCommand.h"
#include "io/files/OutputDirectory.h"
#include "io/mesh/MeshIO.h"
#include "io/shapes/SyntheticShapes.h"
#include "io/volume/NrrdIO.h"
#include "tests/engine/RobustnessHelpers.h"
#include "tests/support/Bzip2Bytes.h"

namespace fs = std::filesystem;
using namespace skelseg;
using namespace skelseg::test;

namespace {

// ---------------------------------------------------------------------------
// Small valid files the bad cases are derived from (and the tetrahedron,
// kTetraOff, in RobustnessHelpers.h)
// ---------------------------------------------------------------------------

std::string nrrd(const std::string& fields, const std::string& data) {
    return "NRRD0004\n" + fields + "\n" + data;
}
const std::string kUint8Fields = "type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n";
const std::string kEightVoxels("\0\1\1\0\1\0\0\1", 8);

std::string binvox(const std::string& header, const std::string& data) {
    return "#binvox 1\n" + header + data;
}
/// 4x4x4 = 64 voxels: runs of 20 + 24 + 20.
const std::string kBinvoxRuns("\0\x14\1\x18\0\x14", 6);

std::string stlBinary(std::uint32_t claimedTriangles,
                      const std::vector<std::array<float, 9>>& triangles) {
    std::string out(80, ' ');
    out.append(reinterpret_cast<const char*>(&claimedTriangles), 4);
    for (const auto& t : triangles) {
        const float normal[3] = {0, 0, 0};
        out.append(reinterpret_cast<const char*>(normal), 12);
        out.append(reinterpret_cast<const char*>(t.data()), 36);
        out.append(2, '\0');
    }
    return out;
}
const std::vector<std::array<float, 9>> kStlTetra = {
    std::array<float, 9>{0, 0, 0, 1, 0, 0, 0, 1, 0},
    std::array<float, 9>{0, 0, 0, 0, 1, 0, 0, 0, 1},
    std::array<float, 9>{0, 0, 0, 0, 0, 1, 1, 0, 0},
    std::array<float, 9>{1, 0, 0, 0, 0, 1, 0, 1, 0}};

const std::string kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
    "z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kPlyBody = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

// ---------------------------------------------------------------------------
// The table of bad inputs
// ---------------------------------------------------------------------------

struct BadCase {
    std::string name;      // test name: letters, digits, underscores
    std::string fileName;  // created in the test's temporary directory
    std::function<void(const fs::path&)> make;
    std::string problem;  // a phrase the message must contain ("" = any)
    std::vector<std::string> extraArguments = {};
    bool score = false;  // a .seg file, read by `skelseg score`
};

void PrintTo(const BadCase& c, std::ostream* os) {
    *os << c.name;
}

BadCase bytes(std::string name, std::string fileName, std::string content, std::string problem) {
    return {std::move(name), std::move(fileName),
            [content](const fs::path& f) { writeBytes(f, content); }, std::move(problem)};
}

/// `ascii` as UTF-16 with a byte order mark, as Windows PowerShell's `>` and
/// Notepad's "Unicode" write text.
std::string utf16(const std::string& ascii, bool bigEndian = false) {
    std::string out = bigEndian ? "\xFE\xFF" : "\xFF\xFE";
    for (char c : ascii) {
        out += bigEndian ? '\0' : c;
        out += bigEndian ? c : '\0';
    }
    return out;
}
const std::string kUtf16Problem =
    "is UTF-16 text (it starts with a UTF-16 byte order mark); save it as UTF-8";

/// The first bytes of `gzip -c tetra.off`: the header (no name, OS 3), then
/// deflate data that holds a lone carriage return before any line feed.
const std::string kGzipBytes("\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03\x2b\r\x73\x8b", 14);
const std::string kCompressedContentProblem = "is a compressed file or archive (its bytes are ";

/// What a clone without Git LFS leaves in place of a large file.
const std::string kLfsPointer =
    "version https://git-lfs.github.com/spec/v1\n"
    "oid sha256:4d7a214614ab2935c943f9e0ff69d22eadbb8f32b1258daaa5e2ca24d17e2393\n"
    "size 12345\n";

/// `text` with every '\n' a carriage return, as classic Mac OS wrote text.
std::string crLineEnds(std::string text) {
    std::replace(text.begin(), text.end(), '\n', '\r');
    return text;
}
const std::string kCrProblem = "ends its lines with a carriage return alone";

BadCase seg(std::string name, std::string content, std::string problem) {
    BadCase c = bytes(std::move(name), "labels.seg", std::move(content), std::move(problem));
    c.score = true;
    return c;
}

std::vector<BadCase> nrrdCases() {
    const std::string gz = gzipBytes(kEightVoxels);
    const std::string bz2 = bzip2Bytes(kEightVoxels);
    const std::string gzFields = "type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\n";
    std::vector<BadCase> cases = {
        bytes("nrrd_empty", "empty.nrrd", "", "file is empty"),
        bytes("nrrd_wrong_magic", "png.nrrd", "\x89PNG\r\n\x1a\n\0\0\0\rIHDR", "wrong magic"),
        bytes("nrrd_text_not_nrrd", "text.nrrd", "hello world\n", "wrong magic"),
        bytes("nrrd_binary_garbage", "garbage.nrrd",
              std::string("\0\xff\x13\x37\0\0\x80\x01\n\n\0", 11), "wrong magic"),
        bytes("nrrd_future_version", "v9.nrrd", "NRRD0009\n" + kUint8Fields + "\n" + kEightVoxels,
              "unsupported NRRD version"),
        bytes("nrrd_magic_only", "magic.nrrd", "NRRD0004\n", "missing required field 'dimension'"),
        bytes("nrrd_truncated_header", "cut.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsiz",
              "malformed header line"),
        bytes("nrrd_header_without_blank_line", "noblank.nrrd", "NRRD0004\n" + kUint8Fields,
              "does not end with a blank line"),
        bytes("nrrd_missing_sizes", "nosizes.nrrd",
              nrrd("type: uint8\ndimension: 3\nencoding: raw\n", kEightVoxels),
              "missing required field 'sizes'"),
        bytes("nrrd_missing_type", "notype.nrrd",
              nrrd("dimension: 3\nsizes: 2 2 2\nencoding: raw\n", kEightVoxels),
              "missing required field 'type'"),
        bytes("nrrd_missing_encoding", "noencoding.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2 2 2\n", kEightVoxels),
              "missing required field 'encoding'"),
        bytes("nrrd_dimension_2", "dim2.nrrd",
              nrrd("type: uint8\ndimension: 2\nsizes: 4 2\nencoding: raw\n", kEightVoxels),
              "dimension 2 is not supported"),
        // A 4-D file of one volume (the size-1 axis) is read: UnusualInputCli.
        bytes("nrrd_dimension_4_axis_of_size_2", "dim4.nrrd",
              nrrd("type: uint8\ndimension: 4\nsizes: 2 2 1 2\nencoding: raw\n"
                   "kinds: domain domain domain time\n",
                   kEightVoxels),
              "axis 3 (kind 'time') has size 2: the file holds several 3-D volumes"),
        bytes("nrrd_dimension_5", "dim5.nrrd",
              nrrd("type: uint8\ndimension: 5\nsizes: 2 2 2 1 1\nencoding: raw\n", kEightVoxels),
              "dimension 5 is not supported"),
        bytes("nrrd_sizes_count", "sizes2.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 4 2\nencoding: raw\n", kEightVoxels),
              "sizes lists 2 values"),
        bytes("nrrd_size_negative", "negative.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2 -2 2\nencoding: raw\n", kEightVoxels),
              "is not positive"),
        bytes("nrrd_size_zero", "zero.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2 2 0\nencoding: raw\n", ""),
              "is not positive"),
        bytes("nrrd_size_not_integer", "float.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2 2.5 2\nencoding: raw\n", kEightVoxels),
              "is not an integer"),
        bytes("nrrd_size_overflows_int64", "overflow.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2 99999999999999999999 2\nencoding: raw\n",
                   kEightVoxels),
              "overflows a 64-bit integer"),
        bytes("nrrd_size_over_axis_cap", "huge.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 100000 100000 100000\nencoding: gzip\n", gz),
              "over the limit of 8192"),
        bytes("nrrd_size_over_voxel_cap", "cap.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 8192 8192 8192\nencoding: gzip\n", gz),
              "over the limit of 4294967280 voxels"),
        bytes("nrrd_raw_data_short", "short.nrrd", nrrd(kUint8Fields, kEightVoxels.substr(0, 5)),
              "data is too short"),
        bytes("nrrd_raw_data_missing", "nodata.nrrd", nrrd(kUint8Fields, ""), "data is too short"),
        bytes("nrrd_raw_data_long", "long.nrrd", nrrd(kUint8Fields, kEightVoxels + "extra"),
              "data is too long"),
        bytes("nrrd_raw_uint16_short", "short16.nrrd",
              nrrd("type: uint16\nendian: little\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n",
                   kEightVoxels),
              "data is too short"),
        bytes("nrrd_gzip_corrupt", "corrupt.nrrd",
              nrrd(gzFields, gz.substr(0, 10) + std::string(8, '\xa5') + gz.substr(18)), "gzip"),
        bytes("nrrd_gzip_not_gzip", "plain.nrrd", nrrd(gzFields, kEightVoxels),
              "corrupt gzip data"),
        bytes("nrrd_gzip_truncated", "gzcut.nrrd", nrrd(gzFields, gz.substr(0, gz.size() / 2)),
              "too short"),
        bytes("nrrd_gzip_long", "gzlong.nrrd",
              nrrd(gzFields, gzipBytes(kEightVoxels + kEightVoxels)), "data is too long"),
        bytes("nrrd_gzip_cannot_hold", "bomb.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2000 2000 1000\nencoding: gzip\n", gz),
              "cannot hold"),
        bytes("nrrd_encoding_hex", "hex.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: hex\n",
                   "00 01 02 03 04 05 060\n"),
              "hex data ends in the middle of a byte"),
        bytes("nrrd_encoding_bzip2", "bz2.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: bzip2\n",
                   bz2.substr(0, 12) + std::string(8, '\xa5') + bz2.substr(20)),
              "corrupt bzip2 data"),
        bytes("nrrd_encoding_ascii", "ascii.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n",
                   "0 1 0 1\n1 O 1 0\n"),
              "ascii data, line 8: 'O' is not a number"),
        bytes("nrrd_encoding_unknown", "zrl.nrrd",
              nrrd("type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: zrl\n", kEightVoxels),
              "unsupported encoding"),
        bytes("nrrd_line_skip_past_the_data", "lines.nrrd",
              nrrd(kUint8Fields + "line skip: 2\n", "one line\n" + kEightVoxels),
              "line skip 2 passes the end of the data"),
        bytes("nrrd_type_block", "block.nrrd",
              nrrd("type: block\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n", kEightVoxels),
              "unsupported type"),
        bytes("nrrd_missing_endian", "noendian.nrrd",
              nrrd("type: uint16\ndimension: 3\nsizes: 2 2 1\nencoding: raw\n", kEightVoxels),
              "missing field 'endian'"),
        bytes("nrrd_bad_endian", "endian.nrrd",
              nrrd("type: uint16\nendian: middle\ndimension: 3\nsizes: 2 2 1\nencoding: raw\n",
                   kEightVoxels),
              "unknown endian"),
        bytes("nrrd_byte_skip", "skip.nrrd", nrrd(kUint8Fields + "byte skip: -2\n", kEightVoxels),
              "byte skip '-2' is invalid"),
        bytes("nrrd_duplicate_field", "twice.nrrd",
              nrrd(kUint8Fields + "sizes: 2 2 2\n", kEightVoxels), "appears twice"),
        bytes("nrrd_direction_nan", "nan.nrrd",
              nrrd(kUint8Fields + "space directions: (nan,0,0) (0,1,0) (0,0,1)\n", kEightVoxels),
              "not a finite number"),
        bytes("nrrd_direction_count", "dirs.nrrd",
              nrrd(kUint8Fields + "space directions: (1,0,0) (0,1,0)\n", kEightVoxels),
              "lists 2 vectors"),
        bytes("nrrd_direction_2d", "dir2d.nrrd",
              nrrd(kUint8Fields + "space directions: (1,0) (0,1) (1,1)\n", kEightVoxels),
              "only 3D spaces"),
        bytes("nrrd_space_4d", "rast.nrrd", nrrd(kUint8Fields + "space: RAST\n", kEightVoxels),
              "only 3D spaces"),
        bytes("nrrd_space_unknown", "space.nrrd",
              nrrd(kUint8Fields + "space: up-down-sideways\n", kEightVoxels), "unknown space"),
        bytes("nrrd_origin_malformed", "origin.nrrd",
              nrrd(kUint8Fields + "space origin: 1 2 3\n", kEightVoxels), "is not a vector"),
        // Geometry that doubles cannot represent (VolumeGeometry::problemOver).
        bytes("nrrd_origin_too_far_for_the_spacing", "far.nrrd",
              nrrd(kUint8Fields + "space origin: (1e15,0,0)\n", kEightVoxels),
              "world coordinates reach 1e+15, where the voxel step along axis 0 (1) is below "
              "2^-40 of them"),
        bytes("nrrd_spacing_zero", "flat.nrrd",
              nrrd(kUint8Fields + "spacings: 1 0 1\n", kEightVoxels),
              "the voxel step along axis 1 is zero: the voxels have no volume"),
        bytes("nrrd_data_file_missing", "detached.nhdr",
              "NRRD0004\n" + kUint8Fields + "data file: missing.raw\n", "no such file"),
    };
    BadCase directoryData =
        bytes("nrrd_data_file_is_directory", "dirdata.nhdr",
              "NRRD0004\n" + kUint8Fields + "data file: subdir\n", "is a directory");
    const auto writeHeader = directoryData.make;
    directoryData.make = [writeHeader](const fs::path& f) {
        writeHeader(f);
        fs::create_directory(f.parent_path() / "subdir");
    };
    cases.push_back(directoryData);
    BadCase shortData =
        bytes("nrrd_data_file_short", "shortdata.nhdr",
              "NRRD0004\n" + kUint8Fields + "data file: short.raw\n", "data is too short");
    const auto writeShort = shortData.make;
    shortData.make = [writeShort](const fs::path& f) {
        writeShort(f);
        writeBytes(f.parent_path() / "short.raw", "abc");
    };
    cases.push_back(shortData);
    // Data in several files (one 2x2 slice a file): each file is checked
    // as one data file is, and they must add up to the sizes.
    const auto severalFiles = [&](std::string name, std::string fileName, std::string dataFile,
                                  std::string problem) {
        BadCase c =
            bytes(std::move(name), std::move(fileName),
                  "NRRD0004\n" + kUint8Fields + "data file: " + dataFile, std::move(problem));
        const auto writeHeader = c.make;
        c.make = [writeHeader](const fs::path& f) {
            writeHeader(f);
            writeBytes(f.parent_path() / "s0.raw", kEightVoxels.substr(0, 4));
            writeBytes(f.parent_path() / "s1.raw", kEightVoxels.substr(4));
            writeBytes(f.parent_path() / "short.raw", kEightVoxels.substr(4, 3));
        };
        cases.push_back(c);
    };
    severalFiles("nrrd_data_file_list_missing_file", "missing.nhdr", "LIST\ns0.raw\nabsent.raw\n",
                 "data file 'absent.raw': no such file");
    severalFiles("nrrd_data_file_list_too_few", "few.nhdr", "LIST\ns0.raw\n",
                 "data file 'LIST' names 1 file, but sizes 2 2 2 are 2 pieces of 2 dimensions, "
                 "one a file");
    severalFiles("nrrd_data_file_list_short_slice", "short.nhdr", "LIST\ns0.raw\nshort.raw\n",
                 "data file 'short.raw': data is too short: 3 bytes, header says 4");
    severalFiles("nrrd_data_file_pattern_two_conversions", "two.nhdr", "s%d%d.raw 0 1 1\n",
                 "has 2 conversions; it must have exactly one integer conversion");
    severalFiles("nrrd_data_file_pattern_of_a_string", "string.nhdr", "s%s.raw 0 1 1\n",
                 "has '%s', which is not an integer conversion");
    severalFiles("nrrd_data_file_pattern_too_many", "many.nhdr", "s%d.raw 0 2 1\n",
                 "names 3 files, but sizes 2 2 2 are 2 pieces");
    // The system ends a name at its first NUL byte: the header named
    // "d.raw\0x" and d.raw was read.
    BadCase nulInName =
        bytes("nrrd_data_file_name_with_a_nul", "nul.nhdr",
              "NRRD0004\n" + kUint8Fields + "data file: d.raw" + std::string(1, '\0') + "x\n",
              "data file 'd.raw?x': the name holds a NUL byte");
    const auto writeNul = nulInName.make;
    nulInName.make = [writeNul](const fs::path& f) {
        writeNul(f);
        writeBytes(f.parent_path() / "d.raw", kEightVoxels);
    };
    cases.push_back(nulInName);
    return cases;
}

std::vector<BadCase> binvoxCases() {
    const std::string header = "dim 4 4 4\ntranslate 0 0 0\nscale 1\ndata\n";
    return {
        bytes("binvox_empty", "empty.binvox", "", "file is empty"),
        bytes("binvox_wrong_magic", "magic.binvox", "#voxbin 1\n" + header + kBinvoxRuns,
              "wrong magic"),
        bytes("binvox_garbage", "garbage.binvox",
              std::string("\x7f"
                          "ELF\2\1\1\0\0\0",
                          10),
              "wrong magic"),
        bytes("binvox_version_3", "v3.binvox", "#binvox 3\n" + header + kBinvoxRuns,
              "unsupported binvox version"),
        bytes("binvox_missing_dim", "nodim.binvox", binvox("scale 1\ndata\n", kBinvoxRuns),
              "missing 'dim'"),
        bytes("binvox_dim_two_values", "dim2.binvox", binvox("dim 4 4\ndata\n", kBinvoxRuns),
              "needs 3 sizes"),
        bytes("binvox_dim_negative", "negative.binvox", binvox("dim 4 -4 4\ndata\n", kBinvoxRuns),
              "is not positive"),
        bytes("binvox_dim_zero", "zero.binvox", binvox("dim 0 4 4\ndata\n", ""), "is not positive"),
        bytes("binvox_dim_over_axis_cap", "huge.binvox",
              binvox("dim 100000 100000 100000\ndata\n", kBinvoxRuns), "over the limit of 8192"),
        bytes("binvox_dim_overflows_int64", "overflow.binvox",
              binvox("dim 4 99999999999999999999 4\ndata\n", kBinvoxRuns),
              "overflows a 64-bit integer"),
        bytes("binvox_dim_not_integer", "text.binvox", binvox("dim 4 four 4\ndata\n", kBinvoxRuns),
              "is not an integer"),
        bytes("binvox_no_data_line", "nodata.binvox", binvox("dim 4 4 4\n", ""),
              "missing 'data' line"),
        bytes("binvox_data_empty", "empty-data.binvox", binvox(header, ""), "data is too short"),
        bytes("binvox_data_short", "short.binvox", binvox(header, kBinvoxRuns.substr(0, 4)),
              "data is too short"),
        bytes("binvox_truncated_run", "halfrun.binvox",
              binvox("dim 2 2 2\ndata\n", std::string("\1\4\0", 3)), "too short"),
        bytes("binvox_data_long", "long.binvox",
              binvox(header, kBinvoxRuns + std::string("\0\1", 2)), "data is too long"),
        bytes("binvox_odd_trailing_byte", "odd.binvox", binvox(header, kBinvoxRuns + "x"),
              "data is too long"),
        bytes("binvox_run_overflows_grid", "runover.binvox",
              binvox(header, std::string("\0\x14\1\x18\0\x20", 6)), "overflows the 64 voxels"),
        bytes("binvox_scale_zero", "scale0.binvox",
              binvox("dim 4 4 4\nscale 0\ndata\n", kBinvoxRuns), "is not positive"),
        bytes("binvox_scale_nan", "scalenan.binvox",
              binvox("dim 4 4 4\nscale nan\ndata\n", kBinvoxRuns), "not a finite number"),
        bytes("binvox_scale_subnormal", "subnormal.binvox",
              binvox("dim 4 4 4\nscale 1e-320\ndata\n", kBinvoxRuns), "is a subnormal number"),
        bytes("binvox_translate_inf", "inf.binvox",
              binvox("dim 4 4 4\ntranslate 0 inf 0\ndata\n", kBinvoxRuns), "not a finite number"),
    };
}

std::vector<BadCase> meshCases() {
    std::string nanStl = stlBinary(1, {std::array<float, 9>{0, 0, 0, 1, 0, 0, 0, 1, 0}});
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(&nanStl[84 + 12 + 4], &nan, 4);
    std::string plyBinary =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float "
        "y\n"
        "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
    plyBinary += std::string(4 * 12, '\0') + "\x03";  // vertices, then the file ends inside face 0
    std::string plyBinaryTetra = plyBinary;
    plyBinaryTetra.pop_back();
    const std::int32_t tetraFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto& face : tetraFaces) {
        plyBinaryTetra += '\x03';
        plyBinaryTetra.append(reinterpret_cast<const char*>(face), 12);
    }
    const std::string plyHeaderThreeFaces =
        kPlyHeader.substr(0, kPlyHeader.find("element face 4")) + "element face 3" +
        kPlyHeader.substr(kPlyHeader.find("element face 4") + 14);
    return {
        // OFF
        bytes("off_empty", "empty.off", "", "empty file"),
        bytes("off_comments_only", "comments.off", "# nothing\n\n", "empty file"),
        bytes("off_wrong_magic", "magic.off", "OFX\n4 4 0\n", "not an OFF file"),
        bytes("off_binary", "binary.off", "OFF BINARY\n", "binary OFF"),
        bytes("off_counts_missing", "counts.off", "OFF\n", "file ends before"),
        bytes("off_counts_huge", "huge.off", "OFF\n4000000000 4000000000 0\n0 0 0\n",
              "header says"),
        bytes("off_counts_negative", "negative.off", "OFF\n-4 4 0\n0 0 0\n", ""),
        bytes("off_no_faces", "nofaces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "no faces"),
        bytes("off_truncated_vertices", "cutv.off",
              "OFF\n4 4 0\n0 0 0\n1 0 0\n3 0 1 2\n3 0 1 2\n3 0 1 2\n", ""),
        bytes("off_truncated_faces", "cutf.off", kTetraOff.substr(0, kTetraOff.size() - 16),
              "file ends after 2 of 4 faces"),
        bytes("off_counts_over_the_file", "over.off", "OFF\n4 40 0\n" + kTetraBody,
              "header says 4 vertices and 40 faces but only 56 bytes follow"),
        bytes("off_bad_coordinate", "coord.off", "OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n",
              "bad coordinate"),
        bytes("off_nan_coordinate", "nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
              "non-finite"),
        bytes("off_inf_coordinate", "inf.off", "OFF\n3 1 0\n0 0 0\n1 0 -inf\n0 1 0\n3 0 1 2\n",
              "non-finite"),
        bytes("off_index_out_of_range", "range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
              "references vertex 3"),
        bytes("off_index_negative", "negindex.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
              "references vertex"),
        bytes("off_face_two_vertices", "twov.off",
              "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n# padding, so that the counts fit\n",
              "at least 3"),
        bytes("off_face_count_lies", "lies.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n5 0 1 2\n",
              "lists 3 of its 5"),
        bytes("off_face_count_huge", "fhuge.off",
              "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n", ""),
        bytes("off_more_faces_than_declared", "morefaces.off", "OFF\n4 3 0\n" + kTetraBody,
              "line 10: the file holds more faces than its header declares (3)"),
        bytes("off_more_vertices_than_declared", "morevertices.off", "OFF\n3 4 0\n" + kTetraBody,
              "line 6: the file holds more vertices than its header declares (3)"),
        // Geomview's nOFF gives the vertex dimension; only 3 is a shape in space.
        bytes("off_dimension_4", "dim4.off", "nOFF\n4\n4 4 0\n",
              "line 2: 'nOFF' gives vertices 4 coordinates; only 3-dimensional OFF files are "
              "supported"),
        bytes("off_homogeneous_zero", "w0.off", "4OFF\n3 1 0\n0 0 0 1\n1 0 0 0\n0 1 0 1\n3 0 1 2\n",
              "line 4: vertex 1 has the homogeneous coordinate 0 (a point at infinity)"),
        // OBJ
        bytes("obj_empty", "empty.obj", "", "no faces"),
        bytes("obj_vertices_only", "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
        bytes("obj_index_zero", "zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
              "bad face vertex"),
        bytes("obj_index_out_of_range", "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
              "references vertex 4"),
        bytes("obj_index_huge", "hugeidx.obj",
              "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", "bad face vertex"),
        bytes("obj_negative_before_start", "neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n",
              "precede it"),
        bytes("obj_bad_coordinate", "coord.obj", "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n",
              "bad vertex coordinate"),
        bytes("obj_two_coordinates", "twoc.obj", "v 0 0\n", "fewer than 3 coordinates"),
        bytes("obj_nan_coordinate", "nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
              "non-finite"),
        bytes("obj_face_two_vertices", "twov.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "at least 3"),
        // Valid files that are no shape: no face has area, a bounding box
        // over or under what doubles can measure in voxels.
        bytes("obj_all_faces_zero_area", "line.obj",
              "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n", "have zero area"),
        // A sheet in one plane, open or closed as two sides, also tilted
        // to the grid: no volume, where the voxeliser made a one-voxel sheet.
        bytes("obj_flat_sheet", "sheet.obj",
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n", "the mesh is flat"),
        bytes("obj_flat_two_sided_tilted", "tilted.obj",
              "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 2\n", "encloses no volume"),
        bytes("obj_bounding_box_overflows", "huge.obj",
              "v -1e308 0 0\nv 1e308 0 0\nv 0 1e308 0\nf 1 2 3\n", "too large"),
        bytes("obj_bounding_box_huge", "huge.obj", "v 0 0 0\nv 1e150 0 0\nv 0 1e150 0\nf 1 2 3\n",
              "too large"),
        // A unit tetrahedron at 1e15: doubles there step by 0.125, coarser
        // than the voxels (NRRD's "far.nrrd" above, for meshes).
        bytes("obj_too_far_from_the_origin", "far.obj",
              "v 1e15 1e15 1e15\nv 1000000000000001 1e15 1e15\nv 1e15 1000000000000001 1e15\n"
              "v 1e15 1e15 1000000000000001\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
              "2^-40 of them"),
        bytes("obj_bounding_box_subnormal", "subnormal.obj",
              "v 0 0 0\nv 1e-320 0 0\nv 0 1e-320 0\nf 1 2 3\n", "too small"),
        bytes("obj_binary_garbage", "garbage.obj", std::string("\0\1\2\3f\xff\n", 7), ""),
        // STL
        bytes("stl_empty", "empty.stl", "", "not an STL file"),
        bytes("stl_short_binary", "short.stl", std::string(50, '\0'), "not an STL file"),
        bytes("stl_binary_count_mismatch", "count.stl", stlBinary(1000, kStlTetra),
              "binary STL header says"),
        bytes("stl_binary_truncated", "cut.stl",
              stlBinary(4, kStlTetra).substr(0, 84 + 50 * 3 + 20), "binary STL header says"),
        bytes("stl_binary_zero_triangles", "zero.stl", stlBinary(0, {}), "no faces"),
        bytes("stl_binary_nan", "nan.stl", nanStl, "non-finite"),
        bytes("stl_ascii_truncated", "cut-ascii.stl",
              "solid t\n facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n",
              "expected"),
        bytes("stl_ascii_bad_vertex", "badv.stl",
              "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 one 0\nvertex 0 1 "
              "0\nendloop\nendfacet\n"
              "endsolid t\n",
              "bad vertex coordinate"),
        bytes("stl_ascii_no_facets", "nofacets.stl", "solid t\nendsolid t\n", "no faces"),
        bytes("stl_ascii_garbage", "garbage.stl", "solid t\nhello there\n", "expected"),
        // PLY
        bytes("ply_empty", "empty.ply", "", "not a PLY file"),
        bytes("ply_wrong_magic", "magic.ply", "PLY\nformat ascii 1.0\nend_header\n",
              "not a PLY file"),
        bytes("ply_unknown_format", "format.ply",
              "ply\nformat binary_middle_endian 1.0\nend_header\n", "unknown format"),
        bytes("ply_no_end_header", "noend.ply", "ply\nformat ascii 1.0\nelement vertex 4\n",
              "no 'end_header'"),
        bytes("ply_no_format", "noformat.ply", "ply\nelement vertex 0\nend_header\n",
              "no 'format' line"),
        bytes("ply_count_huge", "huge.ply",
              "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float "
              "y\nproperty float z\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n",
              "claims"),
        bytes("ply_property_type", "ptype.ply",
              "ply\nformat ascii 1.0\nelement vertex 1\nproperty quaternion x\nend_header\n",
              "unknown property type"),
        bytes("ply_list_count_float", "listf.ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
              "y\nproperty float z\n"
              "element face 1\nproperty list float int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 "
              "1 0\n3 0 1 2\n",
              "bad list count type"),
        bytes("ply_missing_z", "noz.ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 "
              "1\n3 0 1 2\n",
              "lacks one of the properties"),
        bytes("ply_no_face_element", "noface.ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
              "y\nproperty float z\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n",
              "no face element"),
        bytes("ply_index_out_of_range", "range.ply",
              kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 9\n3 1 2 3\n",
              "references vertex 9"),
        bytes("ply_ascii_truncated", "cut.ply", kPlyHeader + kPlyBody.substr(0, 30), ""),
        bytes("ply_ascii_bad_value", "badval.ply",
              kPlyHeader + "0 0 0\n1 0 0\n0 one 0\n0 0 1\n3 0 2 1\n", "bad"),
        bytes("ply_binary_truncated", "cutbin.ply", plyBinary, "claims 4 items"),
        bytes("ply_ascii_more_faces_than_declared", "morefaces.ply", plyHeaderThreeFaces + kPlyBody,
              "line 17: the file holds more 'face' lines than its header declares (3)"),
        bytes("ply_binary_trailing_bytes", "trailing.ply", plyBinaryTetra + "\x03\x01",
              "2 bytes follow the last element the header declares (4 items of 'face')"),
        // assimp's issue623.ply: the vertex element declares a list its lines
        // do not hold, so the next vertex's x is read as the list's length.
        bytes("ply_vertex_list_not_held", "issue623.ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nproperty list uchar uint vertex_indices\nend_header\n"
              "0.50 0.00 0.00\n1.50 0.00 0.00\n0.00 1.00 0.00\n",
              "line 10: bad vertex value '1.50'"),
        // trimesh's points_emptyascii.ply: one vertex line more than declared,
        // then "element face 0"; the line named the empty 'face' element.
        bytes("ply_extra_vertex_before_empty_face", "extra.ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n",
              "line 13: the file holds more 'vertex' lines than its header declares (3)"),
        // Each reader refused these for another reason: "the mesh has no
        // faces" (OBJ), "it starts with '??O?F?F?'" (OFF), "no 'ply' line".
        bytes("off_utf16", "utf16.off", utf16(kTetraOff), kUtf16Problem),
        bytes("obj_utf16", "utf16.obj",
              utf16("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nv 0 0 1\r\nf 1 3 2\r\nf 1 2 4\r\n"),
              kUtf16Problem),
        bytes("obj_utf16_big_endian", "utf16be.obj",
              utf16("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", true), kUtf16Problem),
        bytes("stl_ascii_utf16", "utf16.stl",
              utf16("solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 "
                    "1 0\nendloop\nendfacet\nendsolid t\n"),
              kUtf16Problem),
        bytes("ply_utf16", "utf16.ply", utf16(kPlyHeader + kPlyBody), kUtf16Problem),
        // Read as one long line: "the mesh has no faces" (OBJ, ASCII STL).
        bytes("off_cr_line_ends", "mac.off", crLineEnds(kTetraOff), kCrProblem),
        bytes("obj_cr_line_ends", "mac.obj",
              crLineEnds("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n"), kCrProblem),
        bytes("stl_ascii_cr_line_ends", "mac.stl",
              crLineEnds("solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 "
                         "0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n"),
              kCrProblem),
        bytes("ply_cr_line_ends", "mac.ply", crLineEnds(kPlyHeader + kPlyBody), kCrProblem),
    };
}

std::vector<BadCase> segCases() {
    const std::string gz = gzipBytes("0\n1\n1\n0\n");
    return {
        seg("seg_empty", "", ""),
        seg("seg_not_integer", "0\n1\nleg\n0\n", "line 3"),
        seg("seg_two_numbers_on_a_line", "0\n1 2\n1\n0\n", "line 2"),
        seg("seg_too_few_labels", "0\n1\n", ""),
        seg("seg_too_many_labels", "0\n1\n1\n0\n1\n", ""),
        seg("seg_utf16", utf16("0\r\n1\r\n1\r\n0\r\n"), kUtf16Problem),
        seg("seg_cr_line_ends", "0\r1\r1\r0\r", kCrProblem),
        seg("seg_gzip_truncated", gz.substr(0, gz.size() - 6), "truncated"),
        seg("seg_gzip_corrupt", gz.substr(0, 10) + std::string(6, '\xee') + gz.substr(16), ""),
        seg("seg_binary_garbage",
            std::string("\x7f"
                        "ELF\2\1\1\0",
                        8),
            ""),
    };
}

/// Files that are not what their name says, or not there at all.
std::vector<BadCase> fileSystemCases() {
    auto directory = [](std::string name, std::string fileName) {
        return BadCase{std::move(name), std::move(fileName),
                       [](const fs::path& f) { fs::create_directory(f); }, "is a directory"};
    };
    auto fifo = [](std::string name, std::string fileName) {
        return BadCase{std::move(name), std::move(fileName),
                       [](const fs::path& f) {
                           ASSERT_EQ(::mkfifo(f.c_str(), 0644), 0) << std::strerror(errno);
                       },
                       "not a regular file"};
    };
    std::vector<BadCase> cases = {
        BadCase{"missing_volume", "missing.nrrd", [](const fs::path&) {}, "no such file"},
        BadCase{"missing_mesh", "missing.off", [](const fs::path&) {}, "no such file"},
        BadCase{"dangling_symlink", "dangling.nrrd",
                [](const fs::path& f) { fs::create_symlink(f.parent_path() / "nowhere.nrrd", f); },
                "no such file"},
        BadCase{"symlink_to_device", "zero.nrrd",
                [](const fs::path& f) { fs::create_symlink("/dev/zero", f); },
                "not a regular file"},
        directory("directory_nrrd", "dir.nrrd"),
        directory("directory_binvox", "dir.binvox"),
        directory("directory_vdb", "dir.vdb"),
        directory("directory_off", "dir.off"),
        directory("directory_ply", "dir.ply"),
        fifo("fifo_nrrd", "fifo.nrrd"),
        fifo("fifo_stl", "fifo.stl"),
        bytes("unknown_extension", "shape.xyz", "NRRD0004\n",
              "unknown input format '.xyz' (skelseg reads .off, .obj, .stl and .ply meshes"),
        // Test-model collections ship meshes zipped or gzipped; the line
        // listed the volume formats only, as if meshes were not read.
        bytes("zip_archive", "model.obj.zip", std::string("PK\x03\x04\x14\0\0\0", 8),
              "is a compressed file or archive ('.zip'); unpack it first (skelseg reads .off"),
        bytes("gzip_stl", "model.STL.GZ", std::string("\x1f\x8b\x08\0", 4),
              "is a compressed file or archive ('.GZ'); unpack it first"),
        // The same content under the name of what it holds ("gzip -c cube.off >
        // cube.off"): the text readers said "ends its lines with a carriage
        // return alone (classic Mac OS text)" (a gzip header often holds a
        // lone CR), STL "not an STL file", NRRD and binvox "wrong magic".
        bytes("gzip_content_off", "gz.off", kGzipBytes, kCompressedContentProblem + "gzip data"),
        bytes("gzip_content_obj", "gz.obj", gzipBytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
              kCompressedContentProblem + "gzip data"),
        bytes("gzip_content_ply", "gz.ply", kGzipBytes, kCompressedContentProblem + "gzip data"),
        bytes("gzip_content_stl", "gz.stl", kGzipBytes, kCompressedContentProblem + "gzip data"),
        bytes("bzip2_content_off", "bz2.off", "BZh91AY&SY\r\x01",
              kCompressedContentProblem + "bzip2 data"),
        bytes("xz_content_obj", "xz.obj", std::string("\xfd\x37\x7a\x58\x5a\x00\r", 7),
              kCompressedContentProblem + "xz data"),
        bytes("zstd_content_ply", "zst.ply", std::string("\x28\xb5\x2f\xfd\r", 5),
              kCompressedContentProblem + "zstd data"),
        bytes("zip_content_stl", "zip.stl", std::string("PK\x03\x04\x14\0\r", 7),
              kCompressedContentProblem + "a zip archive"),
        bytes("gzip_content_nrrd", "gz.nrrd", gzipBytes(nrrd(kUint8Fields, std::string(8, '\1'))),
              kCompressedContentProblem + "gzip data"),
        bytes("gzip_content_binvox", "gz.binvox", kGzipBytes,
              kCompressedContentProblem + "gzip data"),
        bytes("gzip_content_vdb", "gz.vdb", kGzipBytes, kCompressedContentProblem + "gzip data"),
        // What arrives instead of a shape (docs/robustness.md, "A fifth
        // probe"): a clone without Git LFS leaves its pointer, a failed
        // download a web page, and shapes get another format's extension.
        // The OBJ reader said "the mesh has no faces", the STL reader "binary
        // STL header says 845429046 triangles", the others "wrong magic".
        bytes("git_lfs_pointer_obj", "model.obj", kLfsPointer,
              "is a Git LFS pointer (a small text file naming the content by its hash), not the "
              "OBJ data itself; fetch the content with 'git lfs pull'"),
        bytes("git_lfs_pointer_stl", "model.stl", kLfsPointer, "is a Git LFS pointer"),
        bytes("git_lfs_pointer_nrrd", "scan.nrrd", kLfsPointer, "is a Git LFS pointer"),
        bytes("html_page_stl", "download.stl",
              "<!DOCTYPE html>\n<html><head><title>404 Not Found</title></head></html>\n",
              "is an HTML page, not an STL file"),
        bytes("off_content_obj", "tetra.obj", kTetraOff,
              "holds an OFF mesh (it starts with 'OFF'), not an OBJ file as its name says; "
              "rename it to .off"),
        bytes("obj_content_stl", "tetra.stl", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\n",
              "holds an OBJ mesh (it starts with the OBJ statement 'v'), not an STL file as its "
              "name says; rename it to .obj"),
        bytes("ply_content_nrrd", "tetra.nrrd", kPlyHeader + kPlyBody,
              "holds a PLY mesh (its first line is 'ply'), not a NRRD file as its name says; "
              "rename it to .ply"),
        bytes("no_extension", "shape", "NRRD0004\n", "no file extension"),
        bytes("seg_as_input", "labels.seg", "0\n1\n", "unknown input format '.seg'"),
    };
    BadCase seg_directory = directory("seg_directory", "dir.seg");
    seg_directory.score = true;
    cases.push_back(seg_directory);
    BadCase seg_fifo = fifo("seg_fifo", "fifo.seg");
    seg_fifo.score = true;
    cases.push_back(seg_fifo);
    return cases;
}

std::vector<BadCase> allBadCases() {
    std::vector<BadCase> all;
    for (auto part : {nrrdCases(), binvoxCases(), meshCases(), segCases(), fileSystemCases()})
        all.insert(all.end(), part.begin(), part.end());
    return all;
}

class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, ExitsTwoWithOneLineNamingTheFileAndWritesNothing) {
    const BadCase& c = GetParam();
    TempDir dir;
    const fs::path file = dir / c.fileName;
    c.make(file);
    const fs::path out = dir / "out";
    std::vector<std::string> arguments;
    if (c.score) {
        writeBytes(dir / "tetra.off", kTetraOff);
        writeBytes(dir / "human.seg", "0\n1\n1\n0\n");
        arguments = {"score", (dir / "tetra.off").string(), file.string(),
                     (dir / "human.seg").string()};
    } else {
        arguments = {"segment", file.string(), "-o", out.string(), "--quiet"};
        arguments.insert(arguments.end(), c.extraArguments.begin(), c.extraArguments.end());
    }
    std::string before;
    if (fs::is_regular_file(file)) before = fileBytes(file);
    const CliResult result = runSkelseg(arguments, {}, std::chrono::seconds(60));
    EXPECT_TRUE(failsWithOneLine(result, 2, file.string(), c.problem));
    EXPECT_TRUE(leftNothing(out));
    if (fs::is_regular_file(file)) EXPECT_EQ(fileBytes(file), before) << "the input was modified";
}

INSTANTIATE_TEST_SUITE_P(EveryFormat, BadInput, ::testing::ValuesIn(allBadCases()),
                         [](const ::testing::TestParamInfo<BadCase>& info) {
                             return info.param.name;
                         });

TEST(BadInputCli, UnreadableFileIsRefused) {
    TempDir dir;
    const fs::path file = dir / "secret.nrrd";
    writeBytes(file, nrrd(kUint8Fields, kEightVoxels));
    fs::permissions(file, fs::perms::none);
    if (::geteuid() != 0) {
        const CliResult result = runSegment(file, dir / "out");
        EXPECT_TRUE(failsWithOneLine(result, 2, file.string(), "permission denied"));
        EXPECT_TRUE(leftNothing(dir / "out"));
        return;
    }
    // Root reads any file: run a copy of skelseg as nobody, who may create
    // OUTDIR in `dir` but not read the file.
    constexpr uid_t kNobody = 65534;
    constexpr gid_t kNoGroup = 65534;
    for (fs::path parent = dir.path().parent_path(); parent != parent.root_path();
         parent = parent.parent_path())
        if ((fs::status(parent).permissions() & fs::perms::others_exec) == fs::perms::none)
            GTEST_SKIP() << parent << " cannot be entered by other users (TMPDIR)";
    const fs::path binary = dir / "skelseg";
    fs::copy_file(skelsegBinary(), binary);
    fs::permissions(dir.path(), fs::perms::all);
    fs::permissions(binary, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                fs::perms::others_read | fs::perms::others_exec);
    const CliResult result =
        runSkelsegAsUser(kNobody, kNoGroup, binary,
                         {"segment", file.string(), "-o", (dir / "out").string(), "--quiet"});
    EXPECT_TRUE(failsWithOneLine(result, 2, file.string(), "permission denied"));
    EXPECT_TRUE(leftNothing(dir / "out"));
    // The same file with read permission: the refusal was the permission.
    fs::permissions(file, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    const CliResult readable = runSkelsegAsUser(
        kNobody, kNoGroup, binary,
        {"segment", file.string(), "-o", (dir / "out").string(), "--quiet", "--no-preview"});
    EXPECT_EQ(readable.exitCode, 0) << readable.describe();
}

TEST(BadInputCli, ExistingOutdirKeepsOnlyWhatItHeld) {
    TempDir dir;
    const fs::path out = dir / "out";
    fs::create_directory(out);
    writeBytes(out / "notes.txt", "mine");
    writeBytes(dir / "bad.nrrd", "NRRD0004\n");
    const CliResult result = runSegment(dir / "bad.nrrd", out);
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "bad.nrrd").string()));
    EXPECT_EQ(directoryEntries(out), std::vector<std::string>{"notes.txt"});
    EXPECT_EQ(fileBytes(out / "notes.txt"), "mine");
}

TEST(BadInputCli, NestedOutdirIsNotCreated) {
    TempDir dir;
    writeBytes(dir / "bad.off", "OFF\n");
    const CliResult result = runSegment(dir / "bad.off", dir / "a" / "b" / "c");
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "bad.off").string()));
    EXPECT_TRUE(leftNothing(dir / "a"));
}

// ---------------------------------------------------------------------------
// Usage errors and exit codes
// ---------------------------------------------------------------------------

struct UsageCase {
    std::string name;
    std::vector<std::string> arguments;  // {input} is replaced by a valid input, {out} by OUTDIR
    std::string problem;
};

void PrintTo(const UsageCase& c, std::ostream* os) {
    *os << c.name;
}

class UsageErrors : public ::testing::TestWithParam<UsageCase> {};

TEST_P(UsageErrors, ExitTwoWithOneLine) {
    TempDir dir;
    const fs::path input = dir / "box.nrrd";
    writeNrrdMask(input, makeMask(Dims{8, 8, 8}, [](int x, int y, int z) {
                      return x > 1 && x < 6 && y > 1 && y < 6 && z > 1 && z < 6;
                  }));
    std::vector<std::string> arguments;
    for (std::string a : GetParam().arguments) {
        if (a == "{input}") a = input.string();
        if (a.rfind("{out}", 0) == 0) a = (dir / "out").string() + a.substr(5);
        arguments.push_back(a);
    }
    const CliResult result = runSkelseg(arguments);
    EXPECT_TRUE(failsWithOneLine(result, 2, "", GetParam().problem));
    EXPECT_TRUE(leftNothing(dir / "out"));
}

INSTANTIATE_TEST_SUITE_P(
    Cli, UsageErrors,
    ::testing::Values(
        UsageCase{"no_arguments", {}, "subcommand"},
        UsageCase{"unknown_subcommand", {"paint", "{input}"}, ""},
        UsageCase{"missing_output", {"segment", "{input}"}, "--output"},
        UsageCase{"unknown_option", {"segment", "{input}", "-o", "{out}", "--colour"}, "--colour"},
        UsageCase{"unknown_option_with_an_escape",
                  {"segment", "{input}", "-o", "{out}", "--colour\x1b[2J"},
                  "--colour\\x1b[2J"},
        UsageCase{
            "tau_not_a_number", {"segment", "{input}", "-o", "{out}", "--tau", "lots"}, "--tau"},
        UsageCase{"tau_over_100_percent",
                  {"segment", "{input}", "-o", "{out}", "--tau", "150%"},
                  "--tau"},
        UsageCase{"tau_negative", {"segment", "{input}", "-o", "{out}", "--tau", "-1"}, ""},
        UsageCase{
            "sigma_out_of_range", {"segment", "{input}", "-o", "{out}", "--sigma-min", "2"}, ""},
        UsageCase{"sibling_tolerance_out_of_range",
                  {"segment", "{input}", "-o", "{out}", "--sibling-tolerance", "2"},
                  "--sibling-tolerance: Value 2 not in range"},
        UsageCase{"limb_taper_not_a_number",
                  {"segment", "{input}", "-o", "{out}", "--limb-taper", "steep"},
                  "--limb-taper: 'steep' is not a number"},
        UsageCase{"corner_length_out_of_range",
                  {"segment", "{input}", "-o", "{out}", "--corner-length", "50"},
                  "--corner-length: Value 50 not in range"},
        UsageCase{"limb_sigma_margin_out_of_range",
                  {"segment", "{input}", "-o", "{out}", "--limb-sigma-margin", "1.5"},
                  "--limb-sigma-margin: Value 1.5 not in range"},
        UsageCase{"limb_loop_variation_out_of_range",
                  {"segment", "{input}", "-o", "{out}", "--limb-loop-variation", "3"},
                  "--limb-loop-variation: Value 3 not in range"},
        UsageCase{"self_overlap_clearance_out_of_range",
                  {"segment", "{input}", "-o", "{out}", "--self-overlap-clearance", "5"},
                  "--self-overlap-clearance: Value 5 not in range"},
        UsageCase{"sigma_min_nan",
                  {"segment", "{input}", "-o", "{out}", "--sigma-min", "nan"},
                  "not a number"},
        UsageCase{"joint_ratio_nan",
                  {"segment", "{input}", "-o", "{out}", "--joint-ratio", "nan"},
                  "not a number"},
        UsageCase{"bend_angle_without_joints",
                  {"segment", "{input}", "-o", "{out}", "--bend-angle", "30"},
                  "--bend-angle needs --joints"},
        UsageCase{"level_previews_without_levels",
                  {"batch", "{input}", "-o", "{out}", "--level-previews"},
                  "--level-previews needs levels"},
        UsageCase{"junction_merge_radii_nan",
                  {"segment", "{input}", "-o", "{out}", "--junction-merge-radii", "NaN"},
                  "not a number"},
        UsageCase{"max_memory_below_a_byte",
                  {"segment", "{input}", "-o", "{out}", "--max-memory", "0.1"},
                  "less than one byte"},
        UsageCase{"flag_given_a_value",
                  {"segment", "{input}", "-o", "{out}", "--no-stub-limbs=3"},
                  "no-stub-limbs was given a disallowed flag override"},
        UsageCase{"flag_given_false",
                  {"batch", "{input}", "-o", "{out}", "--joints=0"},
                  "joints was given a disallowed flag override"},
        UsageCase{"threads_zero", {"segment", "{input}", "-o", "{out}", "--threads", "0"}, ""},
        // A text that is no number was "Value 12.5 not in range 8 to 2048".
        UsageCase{"resolution_not_an_integer",
                  {"segment", "{input}", "-o", "{out}", "--resolution", "12.5"},
                  "--resolution: '12.5' is not an integer"},
        UsageCase{"threads_not_a_number",
                  {"segment", "{input}", "-o", "{out}", "--threads", "all"},
                  "--threads: 'all' is not an integer"},
        UsageCase{"shapes_in_flight_not_an_integer",
                  {"batch", "{input}", "-o", "{out}", "--shapes-in-flight", "1e3"},
                  "--shapes-in-flight: '1e3' is not an integer"},
        UsageCase{"sigma_min_with_a_unit",
                  {"segment", "{input}", "-o", "{out}", "--sigma-min", "0.5x"},
                  "--sigma-min: '0.5x' is not a number"},
        // An empty output was exit 1 (": cannot create directory: Invalid
        // argument"); an empty input named no file (": no such file").
        UsageCase{"output_empty", {"segment", "{input}", "-o", ""}, "--output: the path is empty"},
        UsageCase{"input_empty", {"segment", "", "-o", "{out}"}, "input: the path is empty"},
        UsageCase{"sequence_output_empty",
                  {"sequence", "{input}", "{input}", "-o", ""},
                  "--output: the path is empty"},
        UsageCase{"resolution_past_64_bits",
                  {"segment", "{input}", "-o", "{out}", "--resolution", "99999999999999999999"},
                  "--resolution: Value 99999999999999999999 not in range"},
        UsageCase{
            "resolution_too_small", {"segment", "{input}", "-o", "{out}", "--resolution", "2"}, ""},
        UsageCase{"mode_unknown", {"segment", "{input}", "-o", "{out}", "--mode", "magic"}, ""},
        UsageCase{"skeleton_search_unknown",
                  {"segment", "{input}", "-o", "{out}", "--skeleton-search", "fast"},
                  "--skeleton-search"},
        UsageCase{
            "exhaustive_contradicts_band",
            {"segment", "{input}", "-o", "{out}", "--exhaustive", "--skeleton-search", "band"},
            "--exhaustive contradicts --skeleton-search band"},
        // The run went ahead without any preview, saying nothing.
        UsageCase{"level_previews_contradict_no_preview",
                  {"batch", "{input}", "-o", "{out}", "--tau", "1%,3%", "--level-previews",
                   "--no-preview"},
                  "--level-previews contradicts --no-preview"},
        // An empty --shard ran the whole manifest, as no --shard does.
        UsageCase{"shard_empty",
                  {"batch", "{input}", "-o", "{out}", "--shard", ""},
                  "--shard: the value is empty; give I/N, e.g. 0/4"},
        UsageCase{"shard_contradicts_shards",
                  {"batch", "{input}", "-o", "{out}", "--shard", "0/2", "--shards", "3"},
                  "--shard 0/2 contradicts --shards 3"},
        UsageCase{"time_budget_negative",
                  {"segment", "{input}", "-o", "{out}", "--time-budget", "-1"},
                  "not a positive number of seconds"},
        UsageCase{
            "time_limit_negative", {"segment", "{input}", "-o", "{out}", "--time-limit", "-1"}, ""},
        UsageCase{"max_memory_text",
                  {"segment", "{input}", "-o", "{out}", "--max-memory", "lots"},
                  "--max-memory"},
        UsageCase{"max_memory_unit",
                  {"segment", "{input}", "-o", "{out}", "--max-memory", "4X"},
                  "unknown unit"},
        UsageCase{"max_memory_zero",
                  {"segment", "{input}", "-o", "{out}", "--max-memory", "0"},
                  "--max-memory"},
        // An empty value ("$MEM" unset) ran with the default; "nan" was told
        // it must be positive; "inf" was no limit.
        UsageCase{"max_memory_empty",
                  {"segment", "{input}", "-o", "{out}", "--max-memory", ""},
                  "--max-memory: the value is empty; give a size such as 4G"},
        UsageCase{"max_memory_nan",
                  {"segment", "{input}", "-o", "{out}", "--max-memory", "nan"},
                  "--max-memory 'nan' is not a size such as 4G or 512M"},
        UsageCase{"max_memory_inf",
                  {"segment", "{input}", "-o", "{out}", "--max-memory", "inf"},
                  "--max-memory 'inf' is not a size such as 4G or 512M"},
        // Accepted, and meant "no bends" (or nothing at all) without a word.
        UsageCase{"bend_angle_past_a_half_turn",
                  {"segment", "{input}", "-o", "{out}", "--joints", "--bend-angle", "180.5"},
                  "--bend-angle 180.5: a limb turns by at most 180 degrees"},
        UsageCase{"budget_passes_without_a_budget",
                  {"segment", "{input}", "-o", "{out}", "--budget-passes", "1"},
                  "--budget-passes needs --time-budget"},
        UsageCase{"budget_calibration_without_a_budget",
                  {"segment", "{input}", "-o", "{out}", "--budget-calibration", "cpu"},
                  "--budget-calibration needs --time-budget"},
        // -1 and values past 2^64 became 18446744073709551615.
        UsageCase{"generate_negative_seed",
                  {"generate", "box", "-o", "{out}.nrrd", "--noise", "0.1", "--seed", "-1"},
                  "'-1' is not a whole number from 0 to 18446744073709551615"},
        UsageCase{"generate_seed_past_64_bits",
                  {"generate", "box", "-o", "{out}.nrrd", "--noise", "0.1", "--seed",
                   "18446744073709551616"},
                  "is not a whole number"},
        UsageCase{"grid_name_for_nrrd",
                  {"segment", "{input}", "-o", "{out}", "--quiet", "--grid", "density"},
                  "grid name applies only to OpenVDB"},
        UsageCase{"generate_unknown_shape", {"generate", "teapot", "-o", "{out}.nrrd"}, "teapot"},
        UsageCase{"generate_bad_extension",
                  {"generate", "sphere", "-o", "{out}.png"},
                  ".nrrd or .binvox"}),
    [](const ::testing::TestParamInfo<UsageCase>& info) { return info.param.name; });

// `generate -o G.NRRD` was refused although every reader takes the
// extension in any case; the largest seed is a seed.
TEST(ExitCodes, GenerateTakesAnUpperCaseExtensionAndTheLargestSeed) {
    TempDir dir;
    const CliResult upper =
        runSkelseg({"generate", "box", "-o", (dir / "G.NRRD").string(), "--size", "16", "--noise",
                    "0.1", "--seed", "18446744073709551615"});
    ASSERT_EQ(upper.exitCode, 0) << upper.describe();
    EXPECT_EQ(readNrrdMask(dir / "G.NRRD").dims().x, 16);
    const CliResult binvox =
        runSkelseg({"generate", "box", "-o", (dir / "b.BinVox").string(), "--size", "16"});
    ASSERT_EQ(binvox.exitCode, 0) << binvox.describe();
    EXPECT_TRUE(fs::exists(dir / "b.BinVox"));
}

// Options of the other kind of input change nothing, and the run says so
// on stderr and in report.json instead of ignoring them without a word.
TEST(CliWarnings, OptionsOfTheOtherKindOfInputAreNamedAndChangeNothing) {
    TempDir dir;
    const fs::path volume = dir / "box.nrrd";
    ASSERT_EQ(runSkelseg({"generate", "box", "-o", volume.string(), "--size", "16"}).exitCode, 0);
    const CliResult plain =
        runSkelseg({"segment", volume.string(), "-o", (dir / "plain").string(), "-q"});
    ASSERT_EQ(plain.exitCode, 0) << plain.describe();
    EXPECT_EQ(plain.err, "");
    const CliResult withMeshOptions =
        runSkelseg({"segment", volume.string(), "-o", (dir / "mesh-options").string(), "-q",
                    "--resolution", "64", "--contact-patch-seams"});
    ASSERT_EQ(withMeshOptions.exitCode, 0) << withMeshOptions.describe();
    const std::string volumeWarning =
        volume.string() +
        ": --resolution and --contact-patch-seams apply only to meshes and are ignored for this "
        "volume";
    EXPECT_EQ(withMeshOptions.err, "skelseg: warning: " + volumeWarning + "\n");
    EXPECT_EQ(readReport(dir / "mesh-options")["warnings"], nlohmann::json::array({volumeWarning}));
    EXPECT_EQ(fileBytes(dir / "mesh-options" / "labels.nrrd"),
              fileBytes(dir / "plain" / "labels.nrrd"));

    // A closed unit cube, faces outward.
    const fs::path mesh = dir / "cube.off";
    writeBytes(mesh,
               "OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
               "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
               "3 3 7 6\n3 3 6 2\n3 0 4 7\n3 0 7 3\n3 1 2 6\n3 1 6 5\n");
    const CliResult withVolumeOption =
        runSkelseg({"segment", mesh.string(), "-o", (dir / "cube").string(), "-q", "--resolution",
                    "16", "--keep-voxel-aspect", "--no-preview"});
    ASSERT_EQ(withVolumeOption.exitCode, 0) << withVolumeOption.describe();
    EXPECT_EQ(withVolumeOption.err,
              "skelseg: warning: " + mesh.string() +
                  ": --keep-voxel-aspect applies only to volumes and is ignored for this mesh\n");
    // --resolution applies to a mesh: no warning names it.
    EXPECT_EQ(withVolumeOption.err.find("--resolution"), std::string::npos);
}

TEST(ExitCodes, HelpAndVersionExitZero) {
    const CliResult help = runSkelseg({"--help"});
    EXPECT_EQ(help.exitCode, 0) << help.describe();
    EXPECT_NE(help.out.find("segment"), std::string::npos);
    const CliResult version = runSkelseg({"--version"});
    EXPECT_EQ(version.exitCode, 0) << version.describe();
    EXPECT_NE(version.out.find("skelseg"), std::string::npos);
}

/// Runs `script` with /bin/sh, skelseg's path in $SKELSEG; the exit status.
int shellStatus(const std::string& script) {
    const std::string command = "SKELSEG='" + skelsegBinary() + "'; export SKELSEG; " + script;
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// `score`'s result, --help and --version go to standard output: a result that
// could not be written there exited 0 and was lost.
TEST(ExitCodes, AResultStandardOutputCannotTakeIsExitOne) {
    TempDir dir;
    const fs::path err = dir / "err.txt";
    EXPECT_EQ(shellStatus("\"$SKELSEG\" --version >/dev/full 2>'" + err.string() + "'"), 1);
    EXPECT_EQ(fileBytes(err),
              "skelseg: error: cannot write to standard output: No space left on device\n");
    EXPECT_EQ(shellStatus("\"$SKELSEG\" --help >&- 2>'" + err.string() + "'"), 1);
    EXPECT_NE(fileBytes(err).find("cannot write to standard output"), std::string::npos);
    // The controls: written, and a reader that stops early took what it wanted.
    EXPECT_EQ(shellStatus("\"$SKELSEG\" --version >/dev/null"), 0);
}

// A reader that closes skelseg's message pipe early (`2>&1 | head -c 1`)
// killed the run with SIGPIPE (exit 141), leaving its staging folder.
TEST(ExitCodes, AClosedMessagePipeDoesNotStopTheRun) {
    TempDir dir;
    const fs::path input = dir / "box.nrrd";
    writeNrrdMask(input, makeMask(Dims{24, 24, 24}, [](int x, int y, int z) {
                      return x > 2 && x < 21 && y > 2 && y < 21 && z > 2 && z < 21;
                  }));
    const fs::path status = dir / "status.txt";
    const int shell = shellStatus(
        "exec bash -c '\"$SKELSEG\" segment \"$0\" -o \"$1\" --no-preview 2>&1 | head -c 1 "
        ">/dev/null; echo ${PIPESTATUS[0]} > \"$2\"' '" +
        input.string() + "' '" + (dir / "out").string() + "' '" + status.string() + "'");
    ASSERT_EQ(shell, 0);
    EXPECT_EQ(fileBytes(status), "0\n");
    EXPECT_TRUE(fs::exists(dir / "out" / "report.json"));
    for (const std::string& name : directoryEntries(dir / "out"))
        EXPECT_EQ(name.rfind(".skelseg-staging", 0), std::string::npos) << name;
}

TEST(ExitCodes, UnwritableOutputIsExitOne) {
    TempDir dir;
    const fs::path input = dir / "box.nrrd";
    writeNrrdMask(input, makeMask(Dims{8, 8, 8}, [](int x, int, int) { return x > 2; }));
    // A directory cannot be created below a regular file (ENOTDIR), even as root.
    writeBytes(dir / "file", "x");
    const CliResult result = runSegment(input, dir / "file" / "out");
    EXPECT_TRUE(
        failsWithOneLine(result, 1, (dir / "file" / "out").string(), "cannot create directory"));
    EXPECT_EQ(fileBytes(dir / "file"), "x");
}

TEST(ExitCodes, OutdirThatIsAFileIsExitTwo) {
    TempDir dir;
    const fs::path input = dir / "box.nrrd";
    writeNrrdMask(input, makeMask(Dims{8, 8, 8}, [](int x, int, int) { return x > 2; }));
    writeBytes(dir / "out", "not a directory");
    const CliResult result = runSegment(input, dir / "out");
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "out").string(), "not a directory"));
    EXPECT_EQ(fileBytes(dir / "out"), "not a directory");
}

TEST(BadInputCli, ScoreOnAMeshWithoutAreaNamesTheMesh) {
    TempDir dir;
    const fs::path mesh = dir / "line.off";
    writeBytes(mesh, "OFF\n4 2 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n3 0 1 2\n3 1 2 3\n");
    writeBytes(dir / "a.seg", "0\n1\n");
    const CliResult result =
        runSkelseg({"score", mesh.string(), (dir / "a.seg").string(), (dir / "a.seg").string()});
    EXPECT_TRUE(failsWithOneLine(result, 2, mesh.string(), "zero area"));
}

TEST(BadInputCli, BatchOutrootThatIsAFileIsExitTwo) {
    TempDir dir;
    writeBytes(dir / "tetra.off", kTetraOff);
    writeBytes(dir / "list.txt", "tetra.off\n");
    writeBytes(dir / "out", "not a directory");
    const CliResult result = runSkelseg({"batch", (dir / "list.txt").string(), "-o",
                                         (dir / "out").string(), "--quiet", "--resolution", "16"});
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "out").string(), "not a directory"));
    EXPECT_EQ(fileBytes(dir / "out"), "not a directory");
}

TEST(BadInputCli, OutdirThatIsADanglingSymlinkIsExitTwoAndTheLinkStays) {
    TempDir dir;
    writeBytes(dir / "tetra.off", kTetraOff);
    writeBytes(dir / "tetra2.off", kTetraOff);
    writeBytes(dir / "list.txt", "tetra.off\n");
    // segment, batch and sequence took the link for a folder they had made
    // when creating it failed (exit 1, "cannot create directory: File
    // exists"), and removed it.
    const std::vector<std::vector<std::string>> commands = {
        {"segment", (dir / "tetra.off").string()},
        {"batch", (dir / "list.txt").string()},
        {"sequence", (dir / "tetra.off").string(), (dir / "tetra2.off").string()}};
    const fs::path link = dir / "out";
    fs::create_symlink(dir / "missing", link);
    for (std::vector<std::string> arguments : commands) {
        for (const char* more : {"-o", "", "--quiet", "--resolution", "16"})
            arguments.push_back(more);
        arguments[arguments.size() - 4] = link.string();
        const CliResult result = runSkelseg(arguments);
        EXPECT_TRUE(failsWithOneLine(
            result, 2, link.string(),
            "is a symbolic link to " + (dir / "missing").string() + ", which does not exist"))
            << arguments[0];
        EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link))) << arguments[0];
        EXPECT_FALSE(fs::exists(dir / "missing")) << arguments[0];
    }
}

TEST(BadInputCli, BatchRefusesAShapeOrBinaryDataAsItsManifest) {
    TempDir dir;
    writeBytes(dir / "tetra.off", kTetraOff);
    writeBytes(dir / "list.txt", std::string("tetra.off\n\0\x01\x02\n", 14));
    for (const fs::path& manifest : {dir / "tetra.off", dir / "list.txt"}) {
        const CliResult result =
            runSkelseg({"batch", manifest.string(), "-o", (dir / "out").string(), "--quiet"});
        EXPECT_TRUE(failsWithOneLine(result, 2, manifest.string(),
                                     manifest == dir / "list.txt" ? "NUL byte" : "not a manifest"));
        EXPECT_TRUE(leftNothing(dir / "out"));
    }
}

/// True if `text` holds a control character other than the newlines that
/// end its lines (what a raw file name would put on the terminal).
bool holdsControlCharacters(const std::string& text) {
    return std::any_of(text.begin(), text.end(), [](char c) {
        const auto byte = static_cast<unsigned char>(c);
        return c != '\n' && (byte < 0x20 || byte == 0x7f);
    });
}

TEST(BadInputCli, FileNameWithControlCharactersIsEscapedOnTheOneLine) {
    TempDir dir;
    // Missing: the message is made before anything is read.
    const fs::path missing = dir / "missing\nname\x1b[2J.off";
    CliResult result = runSegment(missing, dir / "out");
    EXPECT_TRUE(
        failsWithOneLine(result, 2, (dir / "missing\\nname\\x1b[2J.off").string(), "no such file"));
    EXPECT_FALSE(holdsControlCharacters(result.err)) << result.describe();
    EXPECT_TRUE(leftNothing(dir / "out"));
    // Malformed: the reader's message names the file too.
    const fs::path bad = dir / "bad\r\tname.nrrd";
    writeBytes(bad, "NRRD0004\n");
    result = runSegment(bad, dir / "out");
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "bad\\r\\tname.nrrd").string()));
    EXPECT_FALSE(holdsControlCharacters(result.err)) << result.describe();
    EXPECT_TRUE(leftNothing(dir / "out"));
}

TEST(BadInputCli, BatchPrintsFailedInputsWithControlCharactersOnOneLineEach) {
    TempDir dir;
    fs::create_directories(dir / "in");
    writeBytes(dir / "in" / "tetra.off", kTetraOff);
    writeBytes(dir / "in" / "bad\nname.off", "OFF\n");
    // Without --quiet: a line per shape, the counts, the list of failures.
    const CliResult result =
        runSkelseg({"batch", (dir / "in").string(), "-o", (dir / "out").string(), "--resolution",
                    "16", "--no-preview"},
                   {}, std::chrono::seconds(120));
    EXPECT_EQ(result.exitCode, kExitSomeInputsFailed) << result.describe();
    EXPECT_FALSE(holdsControlCharacters(result.err)) << result.describe();
    const auto lines = result.errLines();
    ASSERT_GE(lines.size(), 2u) << result.describe();
    const std::string escaped = (dir / "in" / "bad\\nname.off").string();
    const auto startsWith = [&](const std::string& prefix) {
        return std::count_if(lines.begin(), lines.end(),
                             [&](const std::string& line) { return line.rfind(prefix, 0) == 0; });
    };
    EXPECT_EQ(startsWith("skelseg batch: bad\\nname failed: " + escaped + ": "), 1)
        << result.describe();
    EXPECT_EQ(lines[lines.size() - 2], "skelseg: error: 1 of 2 inputs failed:");
    EXPECT_EQ(lines.back().rfind("  bad\\nname: " + escaped + ": ", 0), 0u) << lines.back();
}

TEST(BadInputCli, BatchRefusesAnInputThatAnotherInputsRunWouldReplace) {
    TempDir dir;
    writeBytes(dir / "a.off", kTetraOff);
    // An earlier batch's labels fed back into a batch writing to the same
    // OUTROOT: a's run replaced them while "labels" read them (a result
    // depending on the order), and the input changed.
    const fs::path labels = dir / "out" / "a" / "labels.nrrd";
    fs::create_directories(labels.parent_path());
    writeNrrdMask(labels, makeMask(Dims{8, 8, 8}, [](int x, int, int) { return x > 2; }));
    const std::string before = fileBytes(labels);
    writeBytes(dir / "list.txt", "a.off\nout/a/labels.nrrd\n");
    const CliResult result =
        runSkelseg({"batch", (dir / "list.txt").string(), "-o", (dir / "out").string(), "--quiet",
                    "--resolution", "16", "--no-preview"});
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "list.txt").string(),
                                 "line 2: " + (dir / "out" / "a" / "labels.nrrd").string() +
                                     " is labels.nrrd in " + (dir / "out" / "a").string() +
                                     ", which the batch rewrites for " + (dir / "a.off").string() +
                                     "; choose another OUTROOT"));
    EXPECT_EQ(fileBytes(labels), before);
    EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));
    EXPECT_FALSE(fs::exists(dir / "out" / "labels"));
    // Into another OUTROOT the same manifest is fine.
    const CliResult elsewhere =
        runSkelseg({"batch", (dir / "list.txt").string(), "-o", (dir / "out2").string(), "--quiet",
                    "--resolution", "16", "--no-preview"});
    EXPECT_EQ(elsewhere.exitCode, 0) << elsewhere.describe();
    EXPECT_EQ(fileBytes(labels), before);
}

// --grid with a mesh was ignored (exit 0) while a volume that is not .vdb
// refused it.
TEST(BadInputCli, AGridNameWithAMeshIsRefusedAsWithAVolume) {
    TempDir dir;
    writeBytes(dir / "a.off", kTetraOff);
    const CliResult result = runSkelseg({"segment", (dir / "a.off").string(), "-o",
                                         (dir / "out").string(), "--quiet", "--grid", "density"});
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "a.off").string(),
                                 "a grid name applies only to OpenVDB (.vdb) input"));
    EXPECT_FALSE(fs::exists(dir / "out"));
}

const std::string kCubeOffForWarnings =
    "OFF\n8 6 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
    "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";

// A closed box 1000 x 0.001 x 0.001 broke into 7 voxel objects at 48, each
// a segment, without a word.
TEST(BadInputCli, AMeshThatBreaksApartInTheVoxelModelIsSaidSo) {
    TempDir dir;
    writeBytes(dir / "needle.off",
               "OFF\n8 6 0\n0 0 0\n1000 0 0\n0 0.001 0\n1000 0.001 0\n0 0 0.001\n"
               "1000 0 0.001\n0 0.001 0.001\n1000 0.001 0.001\n"
               "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n");
    const CliResult result =
        runSkelseg({"segment", (dir / "needle.off").string(), "-o", (dir / "out").string(),
                    "--quiet", "--resolution", "48", "--no-preview"});
    ASSERT_EQ(result.exitCode, 0) << result.describe();
    const auto report = readReport(dir / "out");
    const std::size_t objects = report.at("objects").size();
    ASSERT_GT(objects, 1u) << "the needle must break apart at 48 for this test";
    const std::string warning = (dir / "needle.off").string() +
                                ": the voxel model at resolution 48 has " +
                                std::to_string(objects) + " objects, the mesh 1 piece";
    EXPECT_NE(result.err.find(warning), std::string::npos) << result.err;
    // A box that stays whole says nothing of the kind.
    writeBytes(dir / "box.off", kCubeOffForWarnings);
    const CliResult box =
        runSkelseg({"segment", (dir / "box.off").string(), "-o", (dir / "box").string(), "--quiet",
                    "--resolution", "48", "--no-preview"});
    ASSERT_EQ(box.exitCode, 0) << box.describe();
    EXPECT_EQ(box.err.find("objects, the mesh"), std::string::npos) << box.err;
}

// On the first run these lines were missing inputs (their outputs did not
// exist yet) and the batch ran; the same command then refused them (OUTROOT
// a folder of outputs, the labels another input's output).
TEST(BadInputCli, BatchRefusesOutrootAndAnotherInputsOutputsBeforeTheyExist) {
    TempDir dir;
    writeBytes(dir / "a.off", kTetraOff);
    for (const auto& [listed, problem] :
         {std::pair<std::string, std::string>{"out",
                                              "line 2: " + (dir / "out").string() +
                                                  " is OUTROOT, where the batch writes; choose "
                                                  "another OUTROOT"},
          {"out/a/labels.nrrd", "line 2: " + (dir / "out" / "a" / "labels.nrrd").string() +
                                    " is labels.nrrd in " + (dir / "out" / "a").string() +
                                    ", which the batch rewrites for " + (dir / "a.off").string() +
                                    "; choose another OUTROOT"}}) {
        SCOPED_TRACE(listed);
        writeBytes(dir / "list.txt", "a.off\n" + listed + "\n");
        for (int run = 0; run < 2; ++run) {
            // The second run with OUTROOT made, as the first run made it.
            if (run == 1) fs::create_directories(dir / "out");
            const CliResult result =
                runSkelseg({"batch", (dir / "list.txt").string(), "-o", (dir / "out").string(),
                            "--quiet", "--resolution", "16", "--no-preview"});
            EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "list.txt").string(), problem));
            EXPECT_FALSE(fs::exists(dir / "out" / "a")) << "run " << run;
        }
        fs::remove_all(dir / "out");
    }
}

// A folder named like an input is read as a folder of inputs (its shapes;
// this one holds none, which is a warning), never opened as a file.
TEST(BadInputCli, BatchRecordsAFifoAsAFailedInputAndAFolderAsAFolderWithoutBlocking) {
    TempDir dir;
    writeBytes(dir / "tetra.off", kTetraOff);
    // Named like inputs; a volume's name makes the memory estimate peek at
    // its header, a mesh's makes the fingerprint read it.
    ASSERT_EQ(::mkfifo((dir / "pipe.nrrd").c_str(), 0600), 0) << std::strerror(errno);
    ASSERT_EQ(::mkfifo((dir / "fifo.off").c_str(), 0600), 0) << std::strerror(errno);
    fs::create_directories(dir / "folder.off");
    writeBytes(dir / "list.txt", "pipe.nrrd\ntetra.off\nfifo.off\nfolder.off\n");
    const CliResult result =
        runSkelseg({"batch", (dir / "list.txt").string(), "-o", (dir / "out").string(), "--quiet",
                    "--resolution", "16", "--no-preview"},
                   {}, std::chrono::seconds(60));
    ASSERT_EQ(result.signal, 0) << "the batch blocked: " << result.describe();
    EXPECT_EQ(result.exitCode, kExitSomeInputsFailed) << result.describe();
    const auto lines = result.errLines();
    ASSERT_EQ(lines.size(), 4u) << result.describe();
    EXPECT_EQ(lines[0], "skelseg: warning: " + (dir / "list.txt").string() +
                            ":4: " + (dir / "folder.off").string() +
                            " is a directory holding no supported input file; nothing to do for "
                            "it");
    EXPECT_EQ(lines[1], "skelseg: error: 2 of 3 inputs failed:");
    // In manifest order.
    EXPECT_EQ(lines[2],
              "  pipe (line 1): " + (dir / "pipe.nrrd").string() + ": is not a regular file");
    EXPECT_EQ(lines[3],
              "  fifo (line 3): " + (dir / "fifo.off").string() + ": is not a regular file");
    // The regular input next to them was segmented.
    const nlohmann::json summary = nlohmann::json::parse(fileBytes(dir / "out" / "summary.json"));
    EXPECT_EQ(summary.at("counts").at("done"), 1);
    EXPECT_EQ(summary.at("counts").at("failed"), 2);
    EXPECT_TRUE(fs::exists(dir / "out" / "tetra" / "segmentation.seg"));
    EXPECT_FALSE(fs::exists(dir / "out" / "pipe"));
    EXPECT_FALSE(fs::exists(dir / "out" / "fifo"));
    EXPECT_FALSE(fs::exists(dir / "out" / "folder"));
}

// ---------------------------------------------------------------------------
// Unusual but valid input: a result, no error
// ---------------------------------------------------------------------------

TEST(UnusualInputCli, ByteOrderMarkBeforeTheFirstObjVertexIsSkipped) {
    TempDir dir;
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    writeBytes(dir / "bom.obj", "\xEF\xBB\xBF" + obj);
    writeBytes(dir / "plain.obj", obj);
    const CliResult bom = runSegment(dir / "bom.obj", dir / "a", {"--resolution", "16"});
    ASSERT_EQ(bom.exitCode, 0) << bom.describe();
    ASSERT_EQ(runSegment(dir / "plain.obj", dir / "b", {"--resolution", "16"}).exitCode, 0);
    EXPECT_EQ(fileBytes(dir / "a" / "segmentation.seg"), fileBytes(dir / "b" / "segmentation.seg"));
}

// Valid NRRD forms that were refused (docs/robustness.md, "A fifth probe"):
// a 4-D file whose fourth axis has size 1, and data in a list of files,
// give the labels of the one 3-D file.
TEST(UnusualInputCli, NrrdOfDimensionFourOrInSeveralFilesIsSegmentedAsTheVolume) {
    TempDir dir;
    const MaskVolume mask = makeMask(Dims{8, 8, 8}, [](int x, int y, int z) {
        return (x > 1 && x < 6 && y > 1 && y < 6 && z > 0 && z < 7) || (x < 2 && y < 2);
    });
    std::string voxels(mask.data(), mask.data() + mask.size());
    const std::string fields = "type: uint8\nencoding: raw\nspacings: 1 1 2";
    writeBytes(dir / "volume.nrrd",
               "NRRD0004\n" + fields + "\ndimension: 3\nsizes: 8 8 8\n\n" + voxels);
    writeBytes(dir / "dim4.nrrd",
               "NRRD0004\n" + fields + " nan\ndimension: 4\nsizes: 8 8 8 1\n\n" + voxels);
    std::string list = "LIST\n";
    for (int z = 0; z < 8; ++z) {
        const std::string name = "z" + std::to_string(z) + ".raw";
        writeBytes(dir / name, voxels.substr(std::size_t(z) * 64, 64));
        list += name + "\n";
    }
    writeBytes(dir / "list.nhdr",
               "NRRD0004\n" + fields + "\ndimension: 3\nsizes: 8 8 8\ndata file: " + list);
    ASSERT_EQ(runSegment(dir / "volume.nrrd", dir / "a").exitCode, 0);
    const LabelVolume expected = readNrrdLabels(dir / "a" / "labels.nrrd");
    for (const char* input : {"dim4.nrrd", "list.nhdr"}) {
        const fs::path out = dir / (std::string(input) + ".out");
        const CliResult result = runSegment(dir / input, out);
        ASSERT_EQ(result.exitCode, 0) << result.describe();
        const LabelVolume labels = readNrrdLabels(out / "labels.nrrd");
        ASSERT_EQ(labels.dims(), expected.dims()) << input;
        EXPECT_TRUE(std::equal(labels.data(), labels.data() + labels.size(), expected.data()))
            << input;
    }
}

TEST(UnusualInputCli, MoreThreadsThanCoresPrintNothing) {
    // oneTBB's "TBB Warning: The number of workers is currently limited to
    // ..." took two lines of stderr under --quiet (a Slurm task's
    // --threads over the cores its cpuset grants).
    TempDir dir;
    const std::string threads =
        std::to_string(std::min(1024u, 2 * std::max(1u, std::thread::hardware_concurrency()) + 1));
    ASSERT_EQ(runSkelseg({"generate", "capsule", "--size", "24", "-o", (dir / "c.nrrd").string()})
                  .exitCode,
              0);
    const CliResult run =
        runSegment(dir / "c.nrrd", dir / "out", {"--no-preview", "--threads", threads});
    ASSERT_EQ(run.exitCode, 0) << run.describe();
    EXPECT_EQ(run.err, "");
    // The run uses the cores it may run on, not the threads asked for (each
    // thread beyond them would only add its caches' memory).
    const nlohmann::json report = nlohmann::json::parse(fileBytes(dir / "out" / "report.json"));
    const int used = report.at("parameters").at("threads").get<int>();
    EXPECT_GE(used, 1);
    EXPECT_LE(used, int(std::max(1u, std::thread::hardware_concurrency())));
    writeBytes(dir / "list.txt", "c.nrrd\n");
    const CliResult batch =
        runSkelseg({"batch", (dir / "list.txt").string(), "-o", (dir / "batch").string(), "--quiet",
                    "--no-preview", "--threads", threads});
    ASSERT_EQ(batch.exitCode, 0) << batch.describe();
    EXPECT_EQ(batch.err, "");
}

TEST(UnusualInputCli, BatchInputsNamedLikeTheSummaryOrWithLongNamesAreSegmented) {
    TempDir dir;
    // Each failed (exit 5): summary.json.off's folder was the summary file
    // ("cannot remove: Not a directory"), and a 251-byte stem in two folders
    // gave "folder-stem", over the 255 bytes of a folder name ("File name too
    // long").
    const std::string stem(251, 'x');
    for (const fs::path& input :
         {fs::path("summary.json.off"), fs::path("summary.csv.off"),
          fs::path(std::string(200, 'p')) / (stem + ".off"), fs::path("qq") / (stem + ".off")}) {
        fs::create_directories((dir / input).parent_path());
        writeBytes(dir / input, kTetraOff);
    }
    writeBytes(dir / "list.txt", "summary.json.off\nsummary.csv.off\n" + std::string(200, 'p') +
                                     "/" + stem + ".off\nqq/" + stem + ".off\n");
    const CliResult result =
        runSkelseg({"batch", (dir / "list.txt").string(), "-o", (dir / "out").string(), "--quiet",
                    "--resolution", "16", "--no-preview"});
    ASSERT_EQ(result.exitCode, 0) << result.describe();
    EXPECT_TRUE(result.errLines().empty()) << result.describe();
    const nlohmann::json summary = nlohmann::json::parse(fileBytes(dir / "out" / "summary.json"));
    EXPECT_EQ(summary.at("counts").at("done"), 4);
    for (const std::string& name :
         {std::string("summary.json-2"), std::string("summary.csv-2"), "ppp-" + stem, "qq-" + stem})
        EXPECT_TRUE(fs::exists(dir / "out" / name / "segmentation.seg")) << name;
    EXPECT_TRUE(fs::is_regular_file(dir / "out" / "summary.csv"));
}

TEST(UnusualInputCli, MeshInTinyUnitsIsSegmentedWithoutLabelsVdb) {
    TempDir dir;
    // A 0.1 mm tetrahedron in metres: OpenVDB's transforms refuse its voxels.
    const fs::path input = dir / "tiny.off";
    writeBytes(input,
               "OFF\n4 4 0\n0 0 0\n1e-4 0 0\n0 1e-4 0\n0 0 1e-4\n"
               "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    const CliResult result = runSegment(input, dir / "out", {"--resolution", "32"});
    ASSERT_EQ(result.exitCode, 0) << result.describe();
    ASSERT_EQ(result.errLines().size(), 1u) << result.describe();
    EXPECT_NE(result.errLines()[0].find("labels.vdb is not written"), std::string::npos);
    EXPECT_TRUE(fs::exists(dir / "out" / "labels.nrrd"));
    EXPECT_TRUE(fs::exists(dir / "out" / "segmentation.seg"));
    EXPECT_FALSE(fs::exists(dir / "out" / "labels.vdb"));
}

TEST(UnusualInputCli, VertexNoFaceUsesFarAwayIsIgnoredWithAWarning) {
    // The tetrahedron plus a vertex no face uses, 1e7 away: "all 4 faces have
    // zero area" (exit 2), as the zero-area check's scale took every vertex.
    // It segments as the tetrahedron does, with one warning.
    TempDir dir;
    const fs::path tetra = dir / "tetra.off", stray = dir / "stray.off";
    writeBytes(tetra, kTetraOff);
    writeBytes(stray,
               "OFF\n5 4 0\n" + kTetraBody.substr(0, 24) + "1e7 0 0\n" + kTetraBody.substr(24));
    const std::vector<std::string> options = {"--resolution", "32", "--no-preview"};
    const CliResult plain = runSegment(tetra, dir / "plain", options);
    ASSERT_EQ(plain.exitCode, 0) << plain.describe();
    const CliResult result = runSegment(stray, dir / "out", options);
    ASSERT_EQ(result.exitCode, 0) << result.describe();
    EXPECT_EQ(result.errLines(),
              std::vector<std::string>{"skelseg: warning: " + stray.string() +
                                       ": 1 vertex is used by no face; it is ignored"});
    for (const char* output : {"labels.nrrd", "segmentation.seg", "cuts.ply", "skeleton.ply"})
        EXPECT_EQ(fileBytes(dir / "out" / output), fileBytes(dir / "plain" / output)) << output;
    const std::string report = fileBytes(dir / "out" / "report.json");
    EXPECT_NE(report.find("\"mesh_degenerate_faces\": 0"), std::string::npos);
    EXPECT_NE(report.find("\"vertices\": 5"), std::string::npos);
}

TEST(UnusualInputCli, FileNameThatIsNotUtf8GivesAValidReport) {
    TempDir dir;
    const fs::path input = dir / "caf\xE9.off";
    writeBytes(input, kTetraOff);
    const CliResult result = runSegment(input, dir / "out", {"--resolution", "16"});
    ASSERT_EQ(result.exitCode, 0) << result.describe();
    std::ifstream report(dir / "out" / "report.json");
    nlohmann::json parsed;
    EXPECT_NO_THROW(parsed = nlohmann::json::parse(report));
    EXPECT_TRUE(parsed.is_object());
}

// ---------------------------------------------------------------------------
// Limits
// ---------------------------------------------------------------------------

TEST(Limits, MaxMemoryOneMegabyteIsExitFourAndWritesNothing) {
    TempDir dir;
    const fs::path input = dir / "sphere.nrrd";
    writeNrrdMask(input, rasterise(makeShape("sphere"), {48, 3}));
    const CliResult result = runSegment(input, dir / "out", {"--max-memory", "1M"});
    EXPECT_TRUE(failsWithOneLine(result, 4, input.string(), "--max-memory"));
    EXPECT_TRUE(leftNothing(dir / "out"));
}

TEST(Limits, FileLargerThanMaxMemoryIsRefusedBeforeReading) {
    TempDir dir;
    const fs::path input = dir / "box.nrrd";
    // 4096 bytes of raw data: over a 1 KB limit before a byte is parsed.
    writeBytes(input, nrrd("type: uint8\ndimension: 3\nsizes: 16 16 16\nencoding: raw\n",
                           std::string(4096, '\1')));
    const CliResult result = runSegment(input, dir / "out", {"--max-memory", "1K"});
    EXPECT_TRUE(failsWithOneLine(result, 4, input.string(), "reading the file needs at least 4.1"));
    EXPECT_TRUE(leftNothing(dir / "out"));
}

TEST(Limits, HugeFileOverMaxMemoryIsRefusedWithoutReadingIt) {
    TempDir dir;
    const fs::path input = dir / "sparse.nrrd";
    writeBytes(input, "NRRD0004\n");
    fs::resize_file(input, std::uintmax_t(3) << 30);  // 3 GiB, sparse: no disk used
    const CliResult result = runSegment(input, dir / "out", {"--max-memory", "1G"});
    EXPECT_TRUE(failsWithOneLine(result, 4, input.string(), "--max-memory"));
    EXPECT_LT(result.seconds, 20.0);
    EXPECT_TRUE(leftNothing(dir / "out"));
}

TEST(Limits, DetachedDataFilesOverMaxMemoryAreRefusedBeforeTheyAreRead) {
    // The header is a few bytes; its data files are read whole with it, so
    // their sizes count against --max-memory before a byte of them is read
    // (the grid check comes after reading, and names no file size).
    TempDir dir;
    const fs::path input = dir / "slabs.nhdr";
    writeBytes(input,
               "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1024 1024 3072\n"
               "encoding: raw\ndata file: slab%d.raw 0 2 1 3\n");
    for (int slab = 0; slab < 3; ++slab) {
        const fs::path data = dir / ("slab" + std::to_string(slab) + ".raw");
        writeBytes(data, "");
        fs::resize_file(data, std::uintmax_t(1) << 30);  // 1 GiB each, sparse
    }
    const CliResult result = runSegment(input, dir / "out", {"--max-memory", "2G"});
    EXPECT_TRUE(failsWithOneLine(result, 4, input.string(),
                                 "reading the file and its data files needs at least 3.2"));
    EXPECT_TRUE(leftNothing(dir / "out"));
}

// A run-length or gzip volume of a few megabytes may claim billions of
// voxels: the reader hands the grid to the --max-memory check before it
// allocates it (a byte per voxel). A file too short to encode its grid at
// all stays bad input, which the reader says first. (OpenVDB files:
// TestRobustnessVdb.cpp.)
TEST(Limits, VolumeHeaderGridOverMaxMemoryIsRefusedBeforeItIsAllocated) {
    TempDir dir;
    const std::string binvoxHeader =
        "#binvox 1\ndim 1600 1600 1600\ntranslate 0 0 0\nscale 1\ndata\n";
    const std::string nrrdHeader =
        nrrd("type: uint8\ndimension: 3\nsizes: 1500 1500 1500\nencoding: gzip\n", "");
    // Zeros (sparse files): enough bytes for the grid at binvox's 255 voxels
    // per two bytes and at deflate's densest; the data is never read.
    const fs::path binvox = dir / "huge.binvox";
    writeBytes(binvox, binvoxHeader);
    fs::resize_file(binvox, 40u << 20);
    const fs::path nrrdGzip = dir / "huge.nrrd";
    writeBytes(nrrdGzip, nrrdHeader);
    fs::resize_file(nrrdGzip, 4u << 20);
    // bzip2 may expand millions of times: a few kilobytes may hold the grid.
    const fs::path nrrdBzip2 = dir / "huge-bzip2.nrrd";
    writeBytes(nrrdBzip2,
               nrrd("type: uint8\ndimension: 3\nsizes: 1500 1500 1500\nencoding: bzip2\n",
                    std::string(4096, '\0')));
    const std::pair<fs::path, std::string> inputs[] = {{binvox, "needs at least 4.10 GB"},
                                                       {nrrdGzip, "needs at least 3.38 GB"},
                                                       {nrrdBzip2, "needs at least 3.38 GB"}};
    for (const auto& [input, maskBytes] : inputs) {
        const CliResult result = runSegment(input, dir / "out", {"--max-memory", "1G"});
        EXPECT_TRUE(failsWithOneLine(result, 4, input.string(), "voxels needs at least"))
            << result.err;
        EXPECT_TRUE(leftNothing(dir / "out"));
        // With a time budget the run could coarsen the grid after reading:
        // only the mask, a byte per voxel, is sure to be needed.
        const CliResult budgeted =
            runSegment(input, dir / "out", {"--max-memory", "1G", "--time-budget", "5"});
        EXPECT_TRUE(failsWithOneLine(budgeted, 4, input.string(), maskBytes)) << budgeted.err;
    }
    // Two bytes of data cannot encode the grid: bad input, whatever the memory.
    const fs::path shortBinvox = dir / "short.binvox";
    writeBytes(shortBinvox, binvoxHeader + std::string("\1\xff", 2));
    const fs::path shortGzip = dir / "short.nrrd";
    writeBytes(shortGzip, nrrdHeader + std::string(64, '\0'));
    // A grid over the readers' caps stays bad input too.
    const fs::path overCap = dir / "over-cap.binvox";
    writeBytes(overCap, "#binvox 1\ndim 8192 8192 8192\ntranslate 0 0 0\nscale 1\ndata\n");
    fs::resize_file(overCap, 40u << 20);
    for (const fs::path& input : {shortBinvox, shortGzip, overCap}) {
        const CliResult result = runSegment(input, dir / "out", {"--max-memory", "1G"});
        EXPECT_TRUE(failsWithOneLine(result, 2, input.string(), "")) << result.err;
    }
}

TEST(Limits, FileOverTheInputCapIsBadInputWhateverTheMemory) {
    TempDir dir;
    for (const char* name : {"sparse.nrrd", "sparse.off"}) {
        const fs::path input = dir / name;
        writeBytes(input, "NRRD0004\n");
        fs::resize_file(input, (std::uintmax_t(16) << 30) + 1);  // one byte over 16 GiB, sparse
        const CliResult result = runSegment(input, dir / "out");
        EXPECT_TRUE(failsWithOneLine(result, 2, input.string(), "over the limit of 16 GiB"));
        EXPECT_LT(result.seconds, 20.0);
        EXPECT_TRUE(leftNothing(dir / "out"));
    }
}

TEST(Limits, MaxMemoryIsCheckedBeforeVoxelisingAMesh) {
    TempDir dir;
    const fs::path input = dir / "tetra.off";
    writeBytes(input, kTetraOff);
    // At --resolution 1024 the grid alone would need gigabytes: refused at once.
    const CliResult result =
        runSegment(input, dir / "out", {"--resolution", "1024", "--max-memory", "1M"});
    EXPECT_TRUE(failsWithOneLine(result, 4, input.string(), "--max-memory"));
    EXPECT_LT(result.seconds, 20.0);
    EXPECT_TRUE(leftNothing(dir / "out"));
}

TEST(Limits, MeshGridOverTheVoxelCapIsRefusedNamingTheFile) {
    TempDir dir;
    const fs::path input = dir / "tetra.off";
    writeBytes(input, kTetraOff);
    // 2048 voxels along the longest side of a cube-like mesh: over kMaxVoxels.
    const CliResult result = runSegment(input, dir / "out", {"--resolution", "2048"});
    EXPECT_TRUE(failsWithOneLine(result, 2, input.string(), "over the limit of 4294967280 voxels"));
    EXPECT_TRUE(leftNothing(dir / "out"));
}

TEST(Limits, MeshCollapsedToAPointIsRefusedNamingTheFile) {
    TempDir dir;
    const fs::path input = dir / "point.off";
    writeBytes(input, "OFF\n3 1 0\n1 1 1\n1 1 1\n1 1 1\n3 0 1 2\n");
    const CliResult result = runSegment(input, dir / "out");
    EXPECT_TRUE(failsWithOneLine(result, 2, input.string(), "one point"));
    EXPECT_TRUE(leftNothing(dir / "out"));
}

TEST(Limits, GridOverTheAxisCapIsRefusedBeforeReadingData) {
    TempDir dir;
    const fs::path input = dir / "huge.nrrd";
    // A header claiming 100000^3 voxels (10^15 bytes) over a few bytes of data.
    writeBytes(
        input,
        nrrd("type: uint8\ndimension: 3\nsizes: 100000 100000 100000\nencoding: raw\n", "abc"));
    const CliResult result = runSegment(input, dir / "out");
    EXPECT_TRUE(failsWithOneLine(result, 2, input.string(), "over the limit of 8192"));
    EXPECT_LT(result.seconds, 20.0);
    EXPECT_TRUE(leftNothing(dir / "out"));
}

TEST(Limits, GridOverTheVoxelCapIsRefused) {
    TempDir dir;
    const fs::path input = dir / "cap.binvox";
    writeBytes(input, binvox("dim 8192 8192 8192\ndata\n", kBinvoxRuns));
    const CliResult result = runSegment(input, dir / "out");
    EXPECT_TRUE(failsWithOneLine(result, 2, input.string(), "over the limit of 4294967280 voxels"));
    EXPECT_TRUE(leftNothing(dir / "out"));
}

// ---------------------------------------------------------------------------
// Outputs: interrupted runs, earlier results, the input
// ---------------------------------------------------------------------------

/// A shape that takes the engine a few seconds at least.
fs::path writeLargeInput(const TempDir& dir) {
    const fs::path input = dir / "figure.nrrd";
    writeNrrdMask(input, rasterise(makeShape("figure"), {160, 3}));
    return input;
}

bool hasStagingDirectory(const fs::path& outdir) {
    for (const auto& e : directoryEntries(outdir))
        if (e.rfind(".skelseg-staging", 0) == 0) return true;
    return false;
}

// A time limit, and a budget that no resolution fits (then a time limit
// too): exit 3, nothing left, and the line names the input and the limit.
TEST(Outputs, TimeLimitIsExitThreeAndLeavesNothing) {
    TempDir dir;
    const fs::path input = dir / "sphere.nrrd";
    writeNrrdMask(input, rasterise(makeShape("sphere"), {64, 3}));
    const std::pair<const char*, const char*> limits[] = {
        {"--time-limit", "time limit reached (--time-limit 0.001 s)"},
        {"--time-budget", "to fit --time-budget 0.001 s"}};
    for (const auto& [option, problem] : limits) {
        const CliResult result = runSegment(input, dir / "out", {option, "0.001"});
        EXPECT_TRUE(failsWithOneLine(result, 3, "sphere.nrrd", problem)) << option;
        EXPECT_TRUE(leftNothing(dir / "out")) << option;
    }
}

TEST(Outputs, TimeLimitKeepsAnExistingOutdirAsItWas) {
    TempDir dir;
    const fs::path input = dir / "sphere.nrrd";
    writeNrrdMask(input, rasterise(makeShape("sphere"), {64, 3}));
    fs::create_directory(dir / "out");
    writeBytes(dir / "out" / "notes.txt", "mine");
    const CliResult result = runSegment(input, dir / "out", {"--time-limit", "0.001"});
    EXPECT_TRUE(failsWithOneLine(result, 3, "sphere.nrrd", "time limit"));
    EXPECT_EQ(directoryEntries(dir / "out"), std::vector<std::string>{"notes.txt"});
}

void expectInterruptedBy(int signalNumber) {
    TempDir dir;
    const fs::path input = writeLargeInput(dir);
    const fs::path out = dir / "out";
    bool sent = false;
    // The staging directory appears after the signal handlers are installed.
    const CliResult result =
        runSkelseg({"segment", input.string(), "-o", out.string(), "--quiet"}, [&](pid_t pid) {
            if (!sent && hasStagingDirectory(out)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(200));
                ::kill(pid, signalNumber);
                sent = true;
            }
        });
    ASSERT_TRUE(sent) << "the run ended before it could be interrupted: " << result.describe();
    EXPECT_TRUE(failsWithOneLine(result, 3, "", "interrupted"));
    EXPECT_TRUE(leftNothing(out));
}

TEST(Outputs, SigintIsExitThreeAndLeavesNothing) {
    expectInterruptedBy(SIGINT);
}
TEST(Outputs, SigtermIsExitThreeAndLeavesNothing) {
    expectInterruptedBy(SIGTERM);
}

// The first signal waits for the next poll, which a run blocked in a system
// call never reaches; the second must end it there and then. Killed, the run
// leaves only its staging directory, and the same command completes after.
TEST(Outputs, ASecondSignalEndsTheRunAtOnceAndTheNextRunCompletes) {
    TempDir dir;
    const fs::path input = writeLargeInput(dir);
    const fs::path out = dir / "out";
    const std::vector<std::string> command = {"segment",    input.string(), "-o",
                                              out.string(), "--quiet",      "--no-preview"};
    bool sent = false;
    const CliResult killed = runSkelseg(command, [&](pid_t pid) {
        if (!sent && hasStagingDirectory(out)) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            ::kill(pid, SIGINT);
            ::kill(pid, SIGTERM);
            sent = true;
        }
    });
    ASSERT_TRUE(sent) << "the run ended before it could be interrupted: " << killed.describe();
    // Both are pending at once, and the kernel picks which to deliver first.
    EXPECT_TRUE(killed.signal == SIGINT || killed.signal == SIGTERM) << killed.describe();
    for (const std::string& entry : directoryEntries(out))
        EXPECT_TRUE(isStagingDirectoryName(entry)) << entry << " left under a final name";

    const CliResult again = runSkelseg(command);
    ASSERT_EQ(again.exitCode, 0) << again.describe();
    EXPECT_TRUE(fs::is_regular_file(out / "report.json"));
    EXPECT_FALSE(hasStagingDirectory(out));
}

TEST(Outputs, EarlierResultsNeedForce) {
    TempDir dir;
    const fs::path input = dir / "box.nrrd";
    writeNrrdMask(input, makeMask(Dims{12, 12, 12}, [](int x, int y, int z) {
                      return x > 1 && x < 10 && y > 1 && y < 10 && z > 1 && z < 10;
                  }));
    const fs::path out = dir / "out";
    const CliResult first = runSegment(input, out, {"--no-preview"});
    ASSERT_EQ(first.exitCode, 0) << first.describe();
    // Mark the earlier results so that a replacement is visible.
    writeBytes(out / "labels.nrrd", "earlier labels");
    writeBytes(out / "report.json", "{\"earlier\": true}");
    const auto before = snapshot(out);

    const CliResult refused = runSegment(input, out);
    EXPECT_TRUE(failsWithOneLine(refused, 2, out.string(), "--force"));
    EXPECT_EQ(snapshot(out), before) << "files changed without --force";

    const CliResult forced = runSegment(input, out, {"--force"});
    ASSERT_EQ(forced.exitCode, 0) << forced.describe();
    EXPECT_EQ(readReport(out)["status"], "ok");
    EXPECT_EQ(readNrrdLabels(out / "labels.nrrd").dims(), (Dims{12, 12, 12}));
    EXPECT_TRUE(fs::exists(out / "preview.png"));
    EXPECT_FALSE(hasStagingDirectory(out));
}

TEST(Outputs, OneEarlierOutputIsEnoughToRefuse) {
    TempDir dir;
    const fs::path input = dir / "box.nrrd";
    writeNrrdMask(input, makeMask(Dims{8, 8, 8}, [](int x, int, int) { return x > 2; }));
    fs::create_directory(dir / "out");
    writeBytes(dir / "out" / "preview.png", "earlier");
    const CliResult refused = runSegment(input, dir / "out");
    EXPECT_TRUE(failsWithOneLine(refused, 2, (dir / "out").string(), "preview.png"));
    EXPECT_EQ(fileBytes(dir / "out" / "preview.png"), "earlier");
    EXPECT_EQ(directoryEntries(dir / "out"), std::vector<std::string>{"preview.png"});
}

// A folder of the user's called levels/ was taken for an earlier run's:
// "holds results of an earlier run (levels)", and --force removed it with
// everything in it (finding 1 of the robustness hunt).
TEST(Outputs, AUsersFolderNamedLevelsIsNeverRemovedEvenWithForce) {
    TempDir dir;
    const fs::path input = dir / "box.nrrd";
    writeNrrdMask(input, makeMask(Dims{8, 8, 8}, [](int x, int, int) { return x > 2; }));
    const fs::path out = dir / "out";
    fs::create_directories(out / "levels" / "world1");
    writeBytes(out / "levels" / "world1" / "map.txt", "precious");
    for (const std::vector<std::string>& extra :
         {std::vector<std::string>{}, std::vector<std::string>{"--force"}}) {
        SCOPED_TRACE(extra.empty() ? "without --force" : "with --force");
        const CliResult result = runSegment(input, out, extra);
        EXPECT_TRUE(failsWithOneLine(result, 2, (out / "levels" / "world1").string(),
                                     "not written by skelseg, but inside levels/"));
        EXPECT_EQ(fileBytes(out / "levels" / "world1" / "map.txt"), "precious");
        EXPECT_EQ(directoryEntries(out), std::vector<std::string>{"levels"});
        EXPECT_EQ(directoryEntries(out / "levels"), std::vector<std::string>{"world1"});
    }
}

// A note put into an earlier hierarchy run's levels/ stops --force, which
// would remove it with the levels; without it the levels are replaced.
TEST(Outputs, AFileOfTheUsersInsideAnEarlierRunsLevelsStopsForce) {
    TempDir dir;
    const auto bar = [](int x, int y, int z) {
        return y > 1 && y < 8 && z > 1 && z < 8 && x > 0 && x < 13;
    };
    writeNrrdMask(dir / "bar.nrrd", makeMask(Dims{14, 10, 10}, bar));
    const fs::path input = dir / "bar.nrrd", out = dir / "out";
    const CliResult hierarchy = runSegment(input, out, {"--no-preview", "--tau", "1%,3%"});
    ASSERT_EQ(hierarchy.exitCode, 0) << hierarchy.describe();
    ASSERT_TRUE(fs::exists(out / "levels" / "0" / "labels.nrrd"));
    writeBytes(out / "levels" / "0" / "notes.txt", "mine");
    const auto before = snapshot(out / "levels" / "0");
    const auto report = fileBytes(out / "report.json");

    const CliResult forced = runSegment(input, out, {"--no-preview", "--force"});
    EXPECT_TRUE(failsWithOneLine(forced, 2, (out / "levels" / "0" / "notes.txt").string(),
                                 "not written by skelseg"));
    EXPECT_EQ(snapshot(out / "levels" / "0"), before);
    EXPECT_EQ(fileBytes(out / "report.json"), report);
    EXPECT_FALSE(hasStagingDirectory(out));

    fs::remove(out / "levels" / "0" / "notes.txt");
    const CliResult replaced = runSegment(input, out, {"--no-preview", "--force"});
    ASSERT_EQ(replaced.exitCode, 0) << replaced.describe();
    EXPECT_FALSE(fs::exists(out / "levels"));
    EXPECT_FALSE(fs::exists(out / "hierarchy.json"));
}

TEST(Outputs, InputIsNeverModified) {
    TempDir dir;
    const fs::path input = dir / "box.nrrd";
    writeNrrdMask(input, makeMask(Dims{10, 10, 10}, [](int x, int y, int z) {
                      return x > 1 && x < 8 && y > 1 && y < 8 && z > 1 && z < 8;
                  }));
    fs::permissions(input, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    const std::string bytesBefore = fileBytes(input);
    const auto timeBefore = fs::last_write_time(input);
    const auto permissionsBefore = fs::status(input).permissions();
    // Output beside the input, a refused second run, a forced third one.
    EXPECT_EQ(runSegment(input, dir.path()).exitCode, 0);
    EXPECT_EQ(runSegment(input, dir.path()).exitCode, 2);
    EXPECT_EQ(runSegment(input, dir.path(), {"--force"}).exitCode, 0);
    EXPECT_EQ(fileBytes(input), bytesBefore);
    EXPECT_EQ(fs::last_write_time(input), timeBefore);
    EXPECT_EQ(fs::status(input).permissions(), permissionsBefore);
}

TEST(Outputs, InputNamedLikeAnOutputIsNotOverwrittenEvenWithForce) {
    TempDir dir;
    const fs::path out = dir / "out";
    fs::create_directory(out);
    const fs::path input = out / "labels.nrrd";  // e.g. a labels.nrrd fed back in
    writeNrrdMask(input, makeMask(Dims{8, 8, 8}, [](int x, int, int) { return x > 2; }));
    const std::string before = fileBytes(input);
    const CliResult result = runSegment(input, out, {"--force"});
    EXPECT_TRUE(failsWithOneLine(result, 2, input.string(), "would be replaced"));
    EXPECT_EQ(fileBytes(input), before);
    EXPECT_EQ(directoryEntries(out), std::vector<std::string>{"labels.nrrd"});
}

// A run without levels removes an earlier run's levels/ on commit: an input
// kept there (a level's labels fed back in) would be lost with --force.
TEST(Outputs, InputInsideAnOutputDirectoryIsNotRemovedEvenWithForce) {
    TempDir dir;
    const fs::path out = dir / "out";
    fs::create_directories(out / "levels" / "0");
    const fs::path input = out / "levels" / "0" / "labels.nrrd";
    writeNrrdMask(input, makeMask(Dims{8, 8, 8}, [](int x, int, int) { return x > 2; }));
    const std::string before = fileBytes(input);
    const CliResult result = runSegment(input, out, {"--force"});
    EXPECT_TRUE(failsWithOneLine(result, 2, input.string(), "is levels in the output directory"));
    EXPECT_EQ(fileBytes(input), before);
    EXPECT_EQ(directoryEntries(out), std::vector<std::string>{"levels"});
}

// A detached NRRD header outside OUTDIR whose data file lies in OUTDIR's
// levels/: the data file is input too.
TEST(Outputs, DetachedDataFileAmongOutputsIsNotRemovedEvenWithForce) {
    TempDir dir;
    const fs::path out = dir / "out";
    fs::create_directories(out / "levels");
    const fs::path data = out / "levels" / "box.raw";
    std::string voxels(8 * 8 * 8, '\0');
    for (std::size_t i = 0; i < voxels.size(); ++i) voxels[i] = (i % 8) > 2 ? 1 : 0;
    writeBytes(data, voxels);
    const fs::path header = dir / "box.nhdr";
    writeBytes(header,
               "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 8 8 8\nencoding: raw\n"
               "data file: out/levels/box.raw\n");
    // Without outputs in the way the header reads (so the refusal below is
    // about the data file's place, not the header).
    const fs::path elsewhere = dir / "elsewhere";
    ASSERT_EQ(runSegment(header, elsewhere).exitCode, 0);
    const CliResult result = runSegment(header, out, {"--force"});
    EXPECT_TRUE(failsWithOneLine(result, 2, header.string(), data.string()));
    EXPECT_EQ(fileBytes(data), voxels);
    EXPECT_EQ(directoryEntries(out), std::vector<std::string>{"levels"});
}

// Another name of a file in an output folder: a path comparison cannot see
// it, but the file is the same (st_dev, st_ino), and a run without levels
// would remove it with levels/.
struct AliasedLevels {
    TempDir dir;
    fs::path out = dir / "out";
    fs::path levelLabels = out / "levels" / "0" / "labels.nrrd";

    AliasedLevels() {
        fs::create_directories(levelLabels.parent_path());
        writeNrrdMask(levelLabels, makeMask(Dims{8, 8, 8}, [](int x, int, int) { return x > 2; }));
    }
};

TEST(Outputs, InputHardLinkedIntoAnOutputDirectoryIsNotRemovedEvenWithForce) {
    AliasedLevels setup;
    const fs::path alias = setup.dir / "alias.nrrd";
    fs::create_hard_link(setup.levelLabels, alias);
    const std::string before = fileBytes(alias);
    const CliResult result = runSegment(alias, setup.out, {"--force"});
    EXPECT_TRUE(failsWithOneLine(result, 2, alias.string(),
                                 "the input is levels/0/labels.nrrd in the output directory and "
                                 "would be replaced"));
    EXPECT_EQ(fileBytes(setup.levelLabels), before);
    EXPECT_EQ(directoryEntries(setup.out), std::vector<std::string>{"levels"});
}

TEST(Outputs, InputThroughASymlinkedFolderIsNotRemovedEvenWithForce) {
    AliasedLevels setup;
    fs::create_directory_symlink(setup.out, setup.dir / "alias");
    const fs::path input = setup.dir / "alias" / "levels" / "0" / "labels.nrrd";
    const std::string before = fileBytes(input);
    const CliResult result = runSegment(input, setup.out, {"--force"});
    EXPECT_TRUE(failsWithOneLine(result, 2, input.string(), "is levels in the output directory"));
    EXPECT_EQ(fileBytes(setup.levelLabels), before);
    EXPECT_EQ(directoryEntries(setup.out), std::vector<std::string>{"levels"});
}

TEST(Outputs, DetachedDataFileHardLinkedIntoAnOutputDirectoryIsNotRemovedEvenWithForce) {
    AliasedLevels setup;
    const fs::path data = setup.out / "levels" / "box.raw";
    std::string voxels(8 * 8 * 8, '\0');
    for (std::size_t i = 0; i < voxels.size(); ++i) voxels[i] = (i % 8) > 2 ? 1 : 0;
    writeBytes(data, voxels);
    fs::create_hard_link(data, setup.dir / "box.raw");
    const fs::path header = setup.dir / "box.nhdr";
    writeBytes(header,
               "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 8 8 8\nencoding: raw\n"
               "data file: box.raw\n");
    const CliResult result = runSegment(header, setup.out, {"--force"});
    EXPECT_TRUE(failsWithOneLine(result, 2, header.string(),
                                 "its data file " + (setup.dir / "box.raw").string() +
                                     " is levels/box.raw in the output directory"));
    EXPECT_EQ(fileBytes(data), voxels);
    EXPECT_EQ(directoryEntries(setup.out), std::vector<std::string>{"levels"});
}

TEST(Outputs, BatchRefusesAnInputHardLinkedIntoAnotherInputsOutputs) {
    TempDir dir;
    writeBytes(dir / "a.off", kTetraOff);
    const fs::path levelLabels = dir / "out" / "a" / "levels" / "0" / "labels.nrrd";
    fs::create_directories(levelLabels.parent_path());
    writeNrrdMask(levelLabels, makeMask(Dims{8, 8, 8}, [](int x, int, int) { return x > 2; }));
    const std::string before = fileBytes(levelLabels);
    fs::create_hard_link(levelLabels, dir / "linked.nrrd");
    writeBytes(dir / "list.txt", "a.off\nlinked.nrrd\n");
    const CliResult result =
        runSkelseg({"batch", (dir / "list.txt").string(), "-o", (dir / "out").string(), "--quiet",
                    "--force", "--resolution", "16", "--no-preview"});
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "list.txt").string(),
                                 "line 2: " + (dir / "linked.nrrd").string() +
                                     " is levels/0/labels.nrrd in " + (dir / "out" / "a").string() +
                                     ", which the batch rewrites for " + (dir / "a.off").string() +
                                     "; choose another OUTROOT"));
    EXPECT_EQ(fileBytes(levelLabels), before);
    EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));
}

TEST(Outputs, SequenceRefusesAFrameHardLinkedIntoItsFrames) {
    TempDir dir;
    writeBytes(dir / "a.off", kTetraOff);
    const fs::path kept = dir / "out" / "frames" / "b" / "b.off";
    fs::create_directories(kept.parent_path());
    writeBytes(kept, kTetraOff);
    fs::create_hard_link(kept, dir / "b.off");
    const CliResult result =
        runSkelseg({"sequence", (dir / "a.off").string(), (dir / "b.off").string(), "-o",
                    (dir / "out").string(), "--quiet", "--force"});
    EXPECT_TRUE(failsWithOneLine(result, 2, (dir / "b.off").string(),
                                 "the frame lies in the output directory's frames/b/b.off and "
                                 "would be replaced"));
    EXPECT_EQ(fileBytes(kept), kTetraOff);
}

/// OUTDIR bind-mounted at another path, in a mount namespace of this test
/// process's own (so nothing leaks to the host); unmounted when done.
class BindMount {
public:
    /// Mounts `source` at `target` (an empty folder); isMounted() is false
    /// where the system does not permit it (not root, no CAP_SYS_ADMIN).
    BindMount(const fs::path& source, const fs::path& target) : mTarget(target) {
        if (::unshare(CLONE_NEWNS) != 0) return;
        if (::mount("none", "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) return;
        mMounted = ::mount(source.c_str(), target.c_str(), nullptr, MS_BIND, nullptr) == 0;
    }
    ~BindMount() {
        if (mMounted) ::umount2(mTarget.c_str(), MNT_DETACH);
    }
    BindMount(const BindMount&) = delete;
    BindMount& operator=(const BindMount&) = delete;

    bool isMounted() const { return mMounted; }

private:
    fs::path mTarget;
    bool mMounted = false;
};

TEST(Outputs, InputThroughABindMountOfTheOutputDirectoryIsNotRemovedEvenWithForce) {
    AliasedLevels setup;
    const fs::path bind = setup.dir / "bind";
    fs::create_directory(bind);
    const BindMount mount(setup.out, bind);
    if (!mount.isMounted()) GTEST_SKIP() << "mount --bind is not permitted here";
    const fs::path input = bind / "levels" / "0" / "labels.nrrd";
    const std::string before = fileBytes(input);
    const CliResult result = runSegment(input, setup.out, {"--force"});
    EXPECT_TRUE(failsWithOneLine(result, 2, input.string(),
                                 "the input is levels/0/labels.nrrd in the output directory"));
    EXPECT_EQ(fileBytes(setup.levelLabels), before);
    EXPECT_EQ(directoryEntries(setup.out), std::vector<std::string>{"levels"});
}

}  // namespace
