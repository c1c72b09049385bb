#include "io/mesh/MeshIO.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <set>

#include "io/mesh/MeshCheck.h"
#include "io/mesh/SegFile.h"
#include "kernels/base/Error.h"
#include "tests/support/TempDir.h"
#include "tests/support/TestPaths.h"

namespace skelseg {
namespace {

using test::TempDir;

// A cube [0,2]^3: 8 vertices, 6 quads, outward orientation.
const double kCubeVertices[8][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0},
                                    {0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}};
const int kCubeQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                              {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

const char* kCubeOff =
    "OFF\n"
    "# a cube\n"
    "8 6 12\n"
    "0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2\n0 2 2\n"
    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

TriangleMesh fromText(MeshFormat format, const std::string& text,
                      const std::string& name = "test") {
    return readMeshFromMemory(name, format, reinterpret_cast<const std::uint8_t*>(text.data()),
                              text.size());
}

void appendFloat(std::string& out, float value, bool bigEndian = false) {
    char bytes[4];
    std::memcpy(bytes, &value, 4);
    if (bigEndian) std::swap(bytes[0], bytes[3]), std::swap(bytes[1], bytes[2]);
    out.append(bytes, 4);
}

void appendUInt32(std::string& out, std::uint32_t value, bool bigEndian = false) {
    char bytes[4];
    std::memcpy(bytes, &value, 4);
    if (bigEndian) std::swap(bytes[0], bytes[3]), std::swap(bytes[1], bytes[2]);
    out.append(bytes, 4);
}

// The cube as 12 triangles (each quad split along its 0-2 diagonal, as a fan).
std::vector<std::array<int, 3>> cubeTriangles() {
    std::vector<std::array<int, 3>> triangles;
    for (const auto& q : kCubeQuads) {
        triangles.push_back({q[0], q[1], q[2]});
        triangles.push_back({q[0], q[2], q[3]});
    }
    return triangles;
}

std::string cubeAsciiStl() {
    std::string out = "solid cube\n";
    for (const auto& t : cubeTriangles()) {
        out += "  facet normal 0 0 0\n    outer loop\n";
        for (int v : t)
            out += "      vertex " + std::to_string(kCubeVertices[v][0]) + " " +
                   std::to_string(kCubeVertices[v][1]) + " " + std::to_string(kCubeVertices[v][2]) +
                   "\n";
        out += "    endloop\n  endfacet\n";
    }
    return out + "endsolid cube\n";
}

std::string cubeBinaryStl(std::uint32_t claimedTriangles = 12) {
    std::string out = "solid this header starts like ASCII on purpose";
    out.resize(80, ' ');
    appendUInt32(out, claimedTriangles);
    for (const auto& t : cubeTriangles()) {
        for (int c = 0; c < 3; ++c) appendFloat(out, 0.0f);
        for (int v : t)
            for (int c = 0; c < 3; ++c) appendFloat(out, float(kCubeVertices[v][c]));
        out += std::string(2, '\0');
    }
    return out;
}

std::string cubeAsciiPly() {
    std::string out =
        "ply\nformat ascii 1.0\ncomment made by hand\n"
        "element vertex 8\nproperty float x\nproperty float y\nproperty float z\nproperty uchar "
        "red\n"
        "element edge 2\nproperty int vertex1\nproperty int vertex2\n"
        "element face 6\nproperty list uchar float texcoord\nproperty list uchar int "
        "vertex_indices\n"
        "end_header\n";
    for (const auto& v : kCubeVertices)
        out += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) +
               " 255\n";
    out += "0 1\n1 2\n";
    for (const auto& q : kCubeQuads)
        out += "2 0.5 0.25 4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " +
               std::to_string(q[2]) + " " + std::to_string(q[3]) + "\n";
    return out;
}

std::string cubeBinaryPly(bool bigEndian) {
    std::string out =
        std::string("ply\nformat ") + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
        " 1.0\n"
        "element vertex 8\nproperty double x\nproperty double y\nproperty double z\nproperty float "
        "nx\n"
        "element face 6\nproperty uchar flags\nproperty list uchar uint vertex_index\n"
        "end_header\n";
    for (const auto& v : kCubeVertices) {
        for (int c = 0; c < 3; ++c) {
            char bytes[8];
            std::memcpy(bytes, &v[c], 8);
            if (bigEndian) std::reverse(bytes, bytes + 8);
            out.append(bytes, 8);
        }
        appendFloat(out, 1.0f, bigEndian);
    }
    for (const auto& q : kCubeQuads) {
        out += char(7);
        out += char(4);
        for (int v : q) appendUInt32(out, std::uint32_t(v), bigEndian);
    }
    return out;
}

std::string cubeObj() {
    // Quads with every index syntax, negative (relative) indices and
    // statements the reader must ignore.
    return "# cube\nmtllib cube.mtl\no cube\n"
           "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nv 0 0 2\nv 2 0 2\nv 2 2 2\nv 0 2 2\n"
           "vt 0 0\nvt 1 0\nvn 0 0 1\ng side\nusemtl red\ns off\n"
           "f 1 4 3 2\n"
           "f 5/1 6/2 7/1 8/2\n"
           "f 1//1 2//1 6//1 5//1\n"
           "f 2/1/1 3/-2/1 7/1/ 6//\n"
           "f -6 -5 -1 -2\n"
           "l 1 2\n"
           "f 4 1 5 8\n";
}

void expectSameMesh(const TriangleMesh& a, const TriangleMesh& b) {
    EXPECT_EQ(a.faceCount, b.faceCount);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.triangleFace, b.triangleFace);
    EXPECT_EQ(a.vertices, b.vertices);
}

TEST(MeshIO, CubeReadsTheSameFromOffObjAndPly) {
    const TriangleMesh off = fromText(MeshFormat::Off, kCubeOff);
    EXPECT_EQ(off.faceCount, 6u);
    EXPECT_EQ(off.vertices.size(), 8u);
    ASSERT_EQ(off.triangles.size(), 12u);
    EXPECT_EQ(off.triangleFace, (std::vector<std::uint32_t>{0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5}));
    // Fan triangulation of quad (0 3 2 1).
    EXPECT_EQ(off.triangles[0], (std::array<std::uint32_t, 3>{0, 3, 2}));
    EXPECT_EQ(off.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 1}));

    expectSameMesh(off, fromText(MeshFormat::Obj, cubeObj()));
    expectSameMesh(off, fromText(MeshFormat::Ply, cubeAsciiPly()));
    expectSameMesh(off, fromText(MeshFormat::Ply, cubeBinaryPly(false)));
    expectSameMesh(off, fromText(MeshFormat::Ply, cubeBinaryPly(true)));
}

TEST(MeshIO, StlAsciiAndBinaryGiveTheSameWeldedMesh) {
    const TriangleMesh ascii = fromText(MeshFormat::Stl, cubeAsciiStl());
    const TriangleMesh binary = fromText(MeshFormat::Stl, cubeBinaryStl());
    EXPECT_EQ(ascii.faceCount, 12u);  // STL has triangles only: one face each
    EXPECT_EQ(ascii.triangles.size(), 12u);
    EXPECT_EQ(ascii.vertices.size(), 8u);  // repeated corners merged
    expectSameMesh(ascii, binary);
    for (std::size_t t = 0; t < 12; ++t) EXPECT_EQ(binary.triangleFace[t], t);
    EXPECT_TRUE(checkMesh(binary).closed);
    // Same triangles as the quads' fans of the OFF cube, in positions.
    const TriangleMesh off = fromText(MeshFormat::Off, kCubeOff);
    for (std::size_t t = 0; t < 12; ++t)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(binary.vertices[binary.triangles[t][c]], off.vertices[off.triangles[t][c]]);
}

TEST(MeshIO, PolygonsMapBackToTheirInputFace) {
    const TriangleMesh mesh = fromText(MeshFormat::Off,
                                       "OFF 6 3 0\n"
                                       "0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 1 0\n5 5 5\n"
                                       "5 0 1 2 3 4\n3 0 1 5\n4 1 2 5 0\n");
    EXPECT_EQ(mesh.faceCount, 3u);
    EXPECT_EQ(mesh.triangleFace, (std::vector<std::uint32_t>{0, 0, 0, 1, 2, 2}));
    EXPECT_EQ(mesh.triangles[2], (std::array<std::uint32_t, 3>{0, 3, 4}));
    EXPECT_EQ(mesh.triangles[5], (std::array<std::uint32_t, 3>{1, 5, 0}));
}

TEST(MeshIO, OffHeaderVariants) {
    // Colour per vertex and per face (COFF), counts after blank and comment
    // lines, CRLF line ends.
    const std::string coff =
        "COFF\r\n\r\n# counts next\r\n3 1 0\r\n0 0 0 255 0 0 255\r\n1 0 0 0 255 0 255\r\n0 1 0 0 0 "
        "255 255\r\n"
        "3 0 1 2 1 0 0\r\n";
    const TriangleMesh mesh = fromText(MeshFormat::Off, coff);
    EXPECT_EQ(mesh.faceCount, 1u);
    EXPECT_EQ(mesh.vertices[1], (std::array<double, 3>{1, 0, 0}));
    EXPECT_EQ(
        fromText(MeshFormat::Off, "NOFF\n3 1\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n")
            .faceCount,
        1u);
    EXPECT_EQ(fromText(MeshFormat::Off, "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").faceCount,
              1u);  // no keyword
}

TEST(MeshIO, ObjForwardAndNegativeIndices) {
    const TriangleMesh mesh =
        fromText(MeshFormat::Obj, "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -1 -2 -3\n");
    EXPECT_EQ(mesh.faceCount, 2u);
    EXPECT_EQ(mesh.triangles[1], (std::array<std::uint32_t, 3>{3, 2, 1}));
}

TEST(MeshIO, ObjBackslashContinuesAStatementOnTheNextLine) {
    // Valid OBJ that exporters write for long faces: it was refused with
    // "bad face vertex '\'".
    const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    const TriangleMesh wrapped = fromText(
        MeshFormat::Obj, vertices + "f 1 2 \\\n  3 4\nf 1 \\ \r\n 3\\\n 4 # done\nv 5 \\\n 5 5\n");
    const TriangleMesh plain =
        fromText(MeshFormat::Obj, vertices + "f 1 2 3 4\nf 1 3 4\nv 5 5 5\n");
    EXPECT_EQ(wrapped.triangles, plain.triangles);
    EXPECT_EQ(wrapped.vertices, plain.vertices);
    // A message names the line the statement starts on.
    try {
        fromText(MeshFormat::Obj, vertices + "f 1 2 \\\n 3 x\n", "wrapped.obj");
        ADD_FAILURE() << "a bad vertex after a continuation was accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("wrapped.obj: line 5: bad face vertex 'x'"),
                  std::string::npos)
            << error.what();
    }
    // A backslash on the last line continues into nothing.
    EXPECT_EQ(fromText(MeshFormat::Obj, vertices + "f 1 2 3 \\").faceCount, 1u);
}

TEST(MeshIO, ObjVertexGluedToANonBreakingSpaceIsRefusedAtItsLine) {
    // "v" and a non-breaking space (text copied from a web page) was skipped
    // as an unknown statement: the vertices after it shifted, and with
    // relative indices the file read as another mesh without a word.
    const std::string nbsp = "\xC2\xA0";
    const std::string text = "v 0 0 0\nv" + nbsp + "1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\n" +
                             "f -5 -3 -4\nf -5 -4 -2\nf -5 -2 -3\nf -4 -3 -2\n";
    try {
        fromText(MeshFormat::Obj, text, "pasted.obj");
        ADD_FAILURE() << "a vertex glued to a non-breaking space was skipped";
    } catch (const InputError& error) {
        EXPECT_EQ(std::string(error.what()),
                  "pasted.obj: line 2: 'v??1' is no statement: a character that is not a space "
                  "or tab follows 'v' (a non-breaking space?)");
    }
    // Other statements may hold any byte: they are not read.
    EXPECT_EQ(fromText(MeshFormat::Obj, "vt" + nbsp +
                                            "0 0\ng caf\xC3\xA9\nv 0 0 0\nv 1 0 0\n"
                                            "v 0 1 0\nf 1 2 3\n")
                  .faceCount,
              1u);
}

struct BadInput {
    MeshFormat format;
    std::string content;
    std::string expected;  // part of the message
};

/// Each case must throw an InputError whose one-line message starts with the
/// file name and contains the expected problem.
void expectEachRefused(const std::vector<BadInput>& cases) {
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const BadInput& bad = cases[i];
        const std::string name = std::string("bad.") + meshFormatName(bad.format);
        try {
            fromText(bad.format, bad.content, name);
            ADD_FAILURE() << "case " << i << " (" << name
                          << ") was accepted; expected: " << bad.expected;
        } catch (const InputError& error) {
            const std::string message = error.what();
            EXPECT_EQ(message.rfind(name + ": ", 0), 0u) << "case " << i << ": " << message;
            EXPECT_NE(message.find(bad.expected), std::string::npos)
                << "case " << i << ": " << message;
            EXPECT_EQ(message.find('\n'), std::string::npos)
                << "case " << i << ": one line expected";
        }
    }
}

TEST(MeshIO, AsciiPlyIgnoresValuesAfterAnItemOnItsLine) {
    // The PLY reference reader (ply.c) reads one item per line and ignores
    // what follows its values; MeshLab wrote trimesh's fuze_ascii.ply with 6
    // undeclared values after each face's colour. It was refused ("face 1 has
    // 1 vertices"): the extra values were read as the next faces.
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
        "property uchar red\nend_header\n";
    const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    const TriangleMesh plain = fromText(
        MeshFormat::Ply, header + vertices + "3 0 2 1 9\n3 0 1 3 9\n3 0 3 2 9\n3 1 2 3 9\n");
    const TriangleMesh extra = fromText(
        MeshFormat::Ply, header + "0 0 0 0 0 -1\n1 0 0 1 0 0\n0 1 0 0 1 0\n0 0 1 0 0 1\n" +
                             "3 0 2 1 9 3 1 1 1\n3 0 1 3 9 3 1 1 1\n3 0 3 2 9\n3 1 2 3 9 2 7 7\n");
    expectSameMesh(extra, plain);
    EXPECT_EQ(extra.faceCount, 4u);
    // A header line of no known keyword is ignored, as ply.c does: Blender
    // 2.4x wrote "Created by ..." without "comment" (assimp's Wuson.ply); it
    // was refused ("unknown header keyword 'Created'").
    std::string blender = header;
    blender.insert(std::string("ply\nformat ascii 1.0\n").size(),
                   "Created by Blender3D 247 - www.blender.org, source file: \n");
    expectSameMesh(fromText(MeshFormat::Ply,
                            blender + vertices + "3 0 2 1 9\n3 0 1 3 9\n3 0 3 2 9\n3 1 2 3 9\n"),
                   plain);
    // An item may still go on on the next line when its own line ends early.
    expectSameMesh(fromText(MeshFormat::Ply, header + "0 0\n0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n9\n" +
                                                 "3 0 1 3 9\n3 0 3 2 9\n3 1 2 3 9\n"),
                   plain);
}

TEST(MeshIO, PlyElementWithoutPropertiesIsSkippedWhateverItsCount) {
    // Found by FuzzPly: an element of no properties holds no data, so the
    // size check cannot bound its count; 4 billion empty items were "read"
    // one by one.
    const std::string tetra =
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const TriangleMesh mesh =
        fromText(MeshFormat::Ply,
                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty "
                 "float y\nproperty float z\nelement nothing 4000000000\n" +
                     tetra);
    EXPECT_EQ(mesh.faceCount, 4u);
    EXPECT_EQ(mesh.vertices.size(), 4u);
    // A face element without properties is refused before memory is
    // reserved for its count (FuzzPly: a 5.7 GB reserve).
    expectEachRefused({{MeshFormat::Ply,
                        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
                        "y\nproperty float z\nelement face 2000000000\nelement face 1\nproperty "
                        "list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                        "the face element has no 'vertex_indices' list"}});
}

TEST(MeshIO, OffKeywordsOfGeomviewsFullSyntax) {
    // Valid OFF that was refused: the first count glued to the keyword
    // (trimesh's whitespace.off, "OFF8 6 12"), homogeneous vertices (4OFF:
    // x y z w, the point (x, y, z) / w) and the dimension given (nOFF, with 3
    // coordinates per vertex; 4nOFF adds w).
    const std::string faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const TriangleMesh plain =
        fromText(MeshFormat::Off, "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + faces);
    const std::vector<std::string> variants = {
        "\t  OFF4 4 0 # a comment\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + faces,
        "COFF4 4\n0 0 0 1 1 1\n1 0 0 1 1 1\n0 1 0 1 1 1\n0 0 1 1 1 1\n" + faces,
        "4OFF\n4 4 0\n0 0 0 1\n2 0 0 2\n0 -1 0 -1\n0 0 0.5 0.5\n" + faces,
        "nOFF\n3\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + faces,
        "nOFF 3 4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + faces,
        "C4nOFF\n3 4 4 0\n0 0 0 1 0 0 0\n3 0 0 3 0 0 0\n0 1 0 1 0 0 0\n0 0 2 2 0 0 0\n" + faces,
    };
    for (const std::string& text : variants) {
        SCOPED_TRACE(text);
        expectSameMesh(fromText(MeshFormat::Off, text), plain);
    }
    expectEachRefused({
        {MeshFormat::Off, "nOFF\n4\n4 4 0\n", "line 2: 'nOFF' gives vertices 4 coordinates"},
        {MeshFormat::Off, "4nOFF 2 4 4 0\n", "'4nOFF' gives vertices 2 coordinates"},
        {MeshFormat::Off, "nOFF\n", "file ends before the dimension that 'nOFF' announces"},
        {MeshFormat::Off, "4OFF\n3 1 0\n0 0 0 1\n1 0 0 0\n0 1 0 1\n3 0 1 2\n",
         "line 4: vertex 1 has the homogeneous coordinate 0"},
        {MeshFormat::Off, "4OFF\n3 1 0\n0 0 0 1\n1 0 0\n0 1 0 1\n3 0 1 2\n",
         "vertex 1 has fewer than 4 coordinates"},
        {MeshFormat::Off, "OFFx 3 1 0\n", "not an OFF file (it starts with 'OFFx')"},
        {MeshFormat::Off, "xOFF 3 1 0\n", "not an OFF file (header 'xOFF')"},
    });
}

// Binary OFF: the cube with 32-bit counts, float vertices (`extraFloats`
// more per vertex, e.g. a normal for NOFF) and for each face its corner
// count and indices, then (Geomview) a colour count and that many floats.
std::string cubeBinaryOff(const std::string& keyword, bool bigEndian, bool faceColours,
                          int extraFloats = 0) {
    std::string out = keyword + " BINARY\n";
    for (std::uint32_t count : {8u, 6u, 12u}) appendUInt32(out, count, bigEndian);
    for (const auto& v : kCubeVertices) {
        for (double c : v) appendFloat(out, float(c), bigEndian);
        for (int e = 0; e < extraFloats; ++e) appendFloat(out, 0.5f, bigEndian);
    }
    for (const auto& q : kCubeQuads) {
        appendUInt32(out, 4, bigEndian);
        for (int i : q) appendUInt32(out, std::uint32_t(i), bigEndian);
        if (!faceColours) continue;
        appendUInt32(out, 3, bigEndian);
        for (int c = 0; c < 3; ++c) appendFloat(out, 1.0f, bigEndian);
    }
    return out;
}

TEST(MeshIO, OffBinaryInGeomviewsAndPmpLayouts) {
    // Valid binary OFF was refused ("binary OFF files are not supported"):
    // pmp-library's data/off/beetle.off and fairing-cross.off (little-endian,
    // no colour count per face); Geomview's own layout is big-endian with one.
    const TriangleMesh ascii = fromText(MeshFormat::Off, kCubeOff);
    for (const bool bigEndian : {true, false})
        for (const bool faceColours : {true, false}) {
            SCOPED_TRACE(std::to_string(bigEndian) + " " + std::to_string(faceColours));
            expectSameMesh(fromText(MeshFormat::Off, cubeBinaryOff("OFF", bigEndian, faceColours)),
                           ascii);
        }
    expectSameMesh(fromText(MeshFormat::Off, cubeBinaryOff("NOFF", true, true, 3)), ascii);
    expectSameMesh(fromText(MeshFormat::Off, cubeBinaryOff("STCOFF", false, false, 6)), ascii);

    std::string shortByOne = cubeBinaryOff("OFF", true, true);
    shortByOne.pop_back();
    std::string badIndex = cubeBinaryOff("OFF", false, false);
    badIndex[badIndex.size() - 1] = '\x7f';  // the last face's last index, little-endian, past 2^30
    expectEachRefused({
        {MeshFormat::Off, "OFF BINARY\n", "binary OFF: the header's counts do not fit the 0 bytes"},
        {MeshFormat::Off, shortByOne, "binary OFF: its faces end before or after the file's end"},
        {MeshFormat::Off, shortByOne + "xy", "binary OFF: its faces end before or after"},
        {MeshFormat::Off, "OFF BINARY 8\n", "line 1: '8' follows 'BINARY' on the header line"},
        {MeshFormat::Off, badIndex, "face 5 references vertex"},
    });
}

TEST(MeshIO, MalformedInputThrowsInputErrorNamingTheFile) {
    const std::string v3 = "0 0 0\n1 0 0\n0 1 0\n";
    // Long enough lines that the counts pass the bytes-left check.
    const std::string v3Long = "0.0000 0.0000 0.0000\n1.0000 0.0000 0.0000\n0.0000 1.0000 0.0000\n";
    std::string truncatedBinaryStl = cubeBinaryStl();
    truncatedBinaryStl.resize(truncatedBinaryStl.size() - 30);
    std::string binaryStlNan = cubeBinaryStl(1).substr(0, 84 + 50);
    const float nan = std::nanf("");
    std::memcpy(&binaryStlNan[84 + 12], &nan, 4);
    std::string truncatedBinaryPly = cubeBinaryPly(false);
    truncatedBinaryPly.resize(truncatedBinaryPly.size() - 5);

    const std::vector<BadInput> cases = {
        {MeshFormat::Off, "", "empty file"},
        {MeshFormat::Off, "hello world\n", "not an OFF file"},
        {MeshFormat::Off, "OFF\n", "counts"},
        {MeshFormat::Off, "OFF\n3 1 0\n" + v3Long.substr(0, 42), "file ends after 2 of 3 vertices"},
        {MeshFormat::Off, "OFF\n3 2 0\n" + v3Long + "3 0 1 2\n", "file ends after 1 of 2 faces"},
        {MeshFormat::Off, "OFF\n3 1 0\n" + v3 + "3 0 1 900\n",
         "face 0 references vertex 900 but there are 3 vertices"},
        {MeshFormat::Off, "OFF\n3 1 0\n" + v3 + "3 0 -1 2\n", "face 0 references vertex -1"},
        {MeshFormat::Off, "OFF\n1000000000 1000000000 0\n" + v3, "header says 1000000000 vertices"},
        {MeshFormat::Off, "OFF\n99999999999999999999 1 0\n",
         "expected vertex, face and edge counts"},
        {MeshFormat::Off, "OFF\n3 0 0\n" + v3, "no faces"},
        {MeshFormat::Off, "OFF\n3 1 0\n" + v3Long + "2 0 1\n", "face 0 has 2 vertices"},
        {MeshFormat::Off, "OFF\n4 4 0\n" + v3 + "0 0 1\n3 0 1 2\n", "file ends after 1 of 4 faces"},
        {MeshFormat::Off, "OFF\n3 1 0\n" + v3 + "4 0 1 2\n", "lists 3 of its 4 vertex indices"},
        {MeshFormat::Off, "OFF\n3 1 0\n0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n",
         "vertex 0 has a non-finite coordinate"},
        {MeshFormat::Off, "OFF\n3 1 0\n0 0 1x\n1 0 0\n0 1 0\n3 0 1 2\n", "bad coordinate"},
        {MeshFormat::Off, "4OFF\n", "counts"},
        {MeshFormat::Obj, "", "no faces"},
        {MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"},
        {MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
         "face 0 references vertex 9 but there are 3 vertices"},
        // An index beyond any mesh's size was reported with that size as
        // the vertex count ("but there are 4294967294 vertices").
        {MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n",
         "face 0 references vertex 99999999999, beyond the 4294967294 vertices a mesh may have"},
        {MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nf 1 2\n", "face 0 has 2 vertices"},
        // trimesh's notenoughindices.obj; the line said "face 0" but not where.
        {MeshFormat::Obj,
         "o s\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl m\ns 1\nf 1// 2//\nf 1// 2// 3//\n",
         "line 7: face 0 has 2 vertices; a face needs at least 3"},
        {MeshFormat::Obj, "v 0 0\n", "fewer than 3 coordinates"},
        {MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "bad face vertex"},
        // Texture and normal indices are not read, but must be indices:
        // "1/zz/qq" was vertex 1.
        {MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/zz/qq 2 3\n",
         "line 4: bad face vertex '1/zz/qq'"},
        {MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2//x 3\n", "bad face vertex '2//x'"},
        {MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/1/1/1\n",
         "bad face vertex '3/1/1/1'"},
        {MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -5 -1 -2\n", "only 3 vertices precede it"},
        {MeshFormat::Obj, "v inf 0 0\n", "non-finite"},
        {MeshFormat::Obj, "\x01\x02garbage\nf a b c\n", "bad face vertex"},
        {MeshFormat::Stl, "", "not an STL file"},
        {MeshFormat::Stl, truncatedBinaryStl, "header says 12 triangles"},
        {MeshFormat::Stl, cubeBinaryStl(0).substr(0, 84), "no faces"},
        {MeshFormat::Stl, binaryStlNan, "non-finite"},
        {MeshFormat::Stl,
         "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n",
         "end of the file"},
        {MeshFormat::Stl, "solid x\n foo\n", "expected 'facet' or 'endsolid'"},
        {MeshFormat::Stl, "solid x\nendsolid x\n", "no faces"},
        {MeshFormat::Stl,
         "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n endloop\n "
         "endfacet\nendsolid\n",
         "face 0 has 2 vertices"},
        {MeshFormat::Ply, "", "not a PLY file"},
        {MeshFormat::Ply, "ply\nformat ascii 1.0\nelement vertex 3\n", "no 'end_header'"},
        {MeshFormat::Ply, "ply\nformat weird 1.0\nend_header\n", "unknown format"},
        {MeshFormat::Ply,
         "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float "
         "y\nproperty float z\nend_header\n0 0 0\n",
         "claims 4000000000 items"},
        {MeshFormat::Ply,
         "ply\nformat binary_little_endian 1.0\nelement vertex 100000\nproperty float x\nproperty "
         "float y\nproperty float z\nend_header\n",
         "claims 100000 items"},
        {MeshFormat::Ply, truncatedBinaryPly, "file ends inside the face data"},
        {MeshFormat::Ply,
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
         "float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
             v3 + "3 0 1 7\n",
         "face 0 references vertex 7 but there are 3 vertices"},
        {MeshFormat::Ply,
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
         "float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
             v3 + "2 0 1\n",
         "face 0 has 2 vertices"},
        {MeshFormat::Ply,
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
         "y\nend_header\n0 0\n1 0\n0 1\n",
         "lacks one of the properties x, y, z"},
        {MeshFormat::Ply,
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
         "float z\nend_header\n" +
             v3,
         "no face element"},
        {MeshFormat::Ply,
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
         "float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0.000000 0.000000 "
         "0.000000\n1.000000 0 0\n0.5\n",
         "file ends inside the vertex data"},
    };
    expectEachRefused(cases);
}

TEST(MeshIO, OffFaceIndicesMayContinueOnTheNextLines) {
    // The cube with its faces wrapped as some writers do (count and first
    // index on one line, each further index on its own), a face colour after
    // the last index, and a comment line inside a face.
    const std::string wrapped =
        "OFF\n8 6 0\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2\n0 2 2\n"
        "4 0 \n3 \n2 \n1 \n4 4 5\n# wrapped\n6 7\n4 0 1 5 4\n4 1 2\n6 5 255 0 0\n"
        "4\n2 3 7 6\n4 3 0 4 7\n";
    expectSameMesh(fromText(MeshFormat::Off, kCubeOff), fromText(MeshFormat::Off, wrapped));
    // The file's end still stops a short face, naming the line it starts on.
    expectEachRefused({{MeshFormat::Off, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0\n1 2\n",
                        "line 6: face 0 lists 3 of its 4 vertex indices"}});
}

TEST(MeshIO, OffFaceColoursAfterTheIndicesAreIgnored) {
    // Geomview's OFF allows a colour after a face's indices: a colour-map
    // index, or 3 or 4 integers 0..255 or reals 0..1. Where the indices are
    // wrapped, the colour is the rest of the line the last index stands on.
    const TriangleMesh cube = fromText(MeshFormat::Off, kCubeOff);
    const std::string header =
        "OFF\n8 6 12\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2\n0 2 2\n";
    for (const std::string colour :
         {" 255 0 0", " 255 0 0 255", " 1.0 0.0 0.0 1.0", " 0.5 0.5 0.5", " 7", "\t0 128 255 "}) {
        std::string text = header;
        for (const auto& q : kCubeQuads)
            text += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " +
                    std::to_string(q[2]) + " " + std::to_string(q[3]) + colour + "\n";
        SCOPED_TRACE(colour);
        expectSameMesh(fromText(MeshFormat::Off, text), cube);
        // COFF's colours per vertex do not change what a face's colour is.
        std::string coff = "C" + text;
        for (const char* corner :
             {"0 0 0", "2 0 0", "2 2 0", "0 2 0", "0 0 2", "2 0 2", "2 2 2", "0 2 2"}) {
            const std::string line = std::string(corner) + "\n";
            coff.replace(coff.find(line), line.size(), std::string(corner) + " 1 1 1 1\n");
        }
        expectSameMesh(fromText(MeshFormat::Off, coff), cube);
    }
    const std::string wrapped = header +
                                "4 0 3\n2 1 255 0 0\n4 4 5 6\n7 0.1 0.2 0.3 1\n4 0 1 5 4 9\n"
                                "4\n1 2 6 5 1 1 1\n4 2 3 7 6\n4 3 0\n4 7 255 255 255 255\n";
    expectSameMesh(fromText(MeshFormat::Off, wrapped), cube);
}

TEST(MeshIO, OffHeaderCountsMayStandOnLinesOfTheirOwn) {
    // Geomview reads the header as tokens; "OFF\n\n\n# hi\n8\n12\n0\n" was
    // refused ("line 5: expected vertex, face and edge counts, found 1
    // numbers"). The edge count stays optional.
    const TriangleMesh cube = fromText(MeshFormat::Off, kCubeOff);
    const std::string vertices = "0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2\n0 2 2\n";
    const std::string faces = "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
    for (const std::string header :
         {"OFF\n\n\n# hi\n8\n6\n12\n", "OFF\n8\n# the faces\n\n6 # six\n0\n", "OFF\n8\n6\n",
          "OFF 8\n6 12\n", "OFF\n8 6\n12\n", "OFF\r\n8\r\n6\r\n0\r\n", "8\n6\n12\n",
          "nOFF\n3\n8\n6\n12\n", "nOFF 3\n8\n6\n"}) {
        SCOPED_TRACE(header);
        expectSameMesh(fromText(MeshFormat::Off, header + vertices + faces), cube);
    }
    expectEachRefused({
        {MeshFormat::Off, "OFF\n8\n", "file ends after the vertex count, before the face count"},
        {MeshFormat::Off, "OFF\n8\n# no more\n", "file ends after the vertex count"},
        {MeshFormat::Off, "OFF\n8\n6 12 0\n" + vertices + faces,
         "line 3: expected vertex, face and edge counts, found 4 numbers"},
        {MeshFormat::Off, "OFF\n8\nsix\n",
         "line 3: expected vertex, face and edge counts, found 'six'"},
        // A line of one number after the counts is the edge count, never a
        // vertex: the vertices then start one line later.
        {MeshFormat::Off, "OFF\n8 6\n0\n" + vertices.substr(6) + faces,
         "file ends after 5 of 6 faces"},
    });
}

TEST(MeshIO, OffFaceOfOneOrTwoVerticesIsNamed) {
    // A face of one vertex, "1 3", made a file whose other lines are as short
    // as they can be look truncated: "header says 4 vertices and 5 faces but
    // only 60 bytes follow" (the bound counted 8 bytes per face).
    const std::string tetra =
        "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    expectEachRefused({
        {MeshFormat::Off, tetra + "1 3\n",
         "bad.off: face 4 has 1 vertices; a face needs at least 3"},
        {MeshFormat::Off, tetra + "1 3", "face 4 has 1 vertices; a face needs at least 3"},
        {MeshFormat::Off, tetra + "2 0 1\n", "face 4 has 2 vertices; a face needs at least 3"},
        {MeshFormat::Off, tetra + "0\n", "face 4 has 0 vertices; a face needs at least 3"},
        {MeshFormat::Off, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1 0\n", "face 0 has 1 vertices"},
        // Counts no file of that size can hold are still refused before
        // anything is reserved for them.
        {MeshFormat::Off, "OFF\n4 40 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n",
         "header says 4 vertices and 40 faces but only 32 bytes follow"},
    });
}

TEST(MeshIO, CompressedContentUnderAMeshExtensionSaysUnpackIt) {
    // "gzip -c cube.off > cube.off": every reader refused it for another,
    // wrong reason ("ends its lines with a carriage return alone", "not an
    // STL file"). Each signature is followed by a lone carriage return, as
    // a gzip header often holds one.
    const std::string tail("\x03\r\x7f\x01\x02", 5);
    const std::vector<std::pair<std::string, std::string>> contents = {
        {"gzip data", std::string("\x1f\x8b\x08\x08\x00\x00\x00\x00\x00\x03", 10) + tail},
        {"bzip2 data", "BZh91AY&SY" + tail},
        {"xz data", std::string("\xfd\x37\x7a\x58\x5a\x00", 6) + tail},
        {"zstd data", std::string("\x28\xb5\x2f\xfd", 4) + tail},
        {"a zip archive", std::string("PK\x03\x04\x14\x00", 6) + tail},
    };
    std::vector<BadInput> cases;
    for (const MeshFormat format :
         {MeshFormat::Off, MeshFormat::Obj, MeshFormat::Stl, MeshFormat::Ply})
        for (const auto& [what, bytes] : contents)
            cases.push_back(
                {format, bytes,
                 "is a compressed file or archive (its bytes are " + what + "); unpack it first"});
    expectEachRefused(cases);
}

TEST(MeshIO, PlyTriangleStripsGiveOneFacePerTriangle) {
    // A tetrahedron as two strips (-1 restarts) with a turn that repeats a
    // vertex: every second triangle flipped, the repeated ones no faces.
    const std::string strips =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
        "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n12 0 1 2 3 3 -1 2 3 0 1 1 1\n";
    const TriangleMesh mesh = fromText(MeshFormat::Ply, strips);
    EXPECT_EQ(mesh.faceCount, 4u);
    EXPECT_EQ(mesh.triangles, (std::vector<std::array<std::uint32_t, 3>>{
                                  {0, 1, 2}, {2, 1, 3}, {2, 3, 0}, {0, 3, 1}}));
    EXPECT_EQ(mesh.triangleFace, (std::vector<std::uint32_t>{0, 1, 2, 3}));
    EXPECT_TRUE(checkMesh(mesh).closed);
}

TEST(MeshIO, DataBeyondTheHeaderCountsIsRefusedNamingWhatIsExtra) {
    const std::string tetraVertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    const std::string tetraFaces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const auto plyHeader = [](int faces) {
        return "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
               "property float z\nelement face " +
               std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
    };
    const std::string binaryPly = cubeBinaryPly(false);
    const std::vector<BadInput> refused = {
        // The header counts 3 of the 4 faces (and 4 of the 4 vertices).
        {MeshFormat::Off, "OFF\n4 3 0\n" + tetraVertices + tetraFaces,
         "line 10: the file holds more faces than its header declares (3)"},
        // The header counts 3 of the 4 vertices: the 4th is read where face 0 belongs.
        {MeshFormat::Off, "OFF\n3 4 0\n" + tetraVertices + tetraFaces,
         "line 6: the file holds more vertices than its header declares (3)"},
        {MeshFormat::Off, "OFF\n4 4 0\n" + tetraVertices + tetraFaces + "end\n",
         "line 11: 'end' follows the last of the 4 faces the header declares"},
        {MeshFormat::Ply, plyHeader(3) + tetraVertices + tetraFaces,
         "line 17: the file holds more 'face' lines than its header declares (3)"},
        {MeshFormat::Ply, binaryPly + std::string("\x03\0\0\0\0", 5),
         "5 bytes follow the last element the header declares (6 items of 'face')"},
        // An element of 0 items last (trimesh's points_emptyascii.ply has
        // "element face 0" after one vertex line too many): the extra line
        // follows the last element that has items; it was "more 'edge' lines
        // than its header declares (0)".
        {MeshFormat::Ply,
         plyHeader(3).insert(plyHeader(3).size() - 11, "element edge 0\nproperty int vertex1\n") +
             tetraVertices + tetraFaces,
         "line 19: the file holds more 'face' lines than its header declares (3)"},
    };
    expectEachRefused(refused);
    // A vertex element declaring a list its lines do not hold (assimp's
    // issue623.ply): the next vertex's x is read as the list's length. The
    // line said "bad vertex value '1.50'" without saying where.
    expectEachRefused({{MeshFormat::Ply,
                        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
                        "y\nproperty float z\nproperty list uchar int vertex_indices\nend_header\n"
                        "0.50 0.00 0.00\n1.50 0.00 0.00\n0.00 1.00 0.00\n",
                        "line 10: bad vertex value '1.50'"}});

    // Whitespace, and in OFF comment lines, may follow the last element.
    EXPECT_EQ(fromText(MeshFormat::Off,
                       "OFF\n4 4 0\n" + tetraVertices + tetraFaces + "\n  \t\r\n# the end\n\n")
                  .faceCount,
              4u);
    EXPECT_EQ(
        fromText(MeshFormat::Ply, plyHeader(4) + tetraVertices + tetraFaces + " \r\n\n").faceCount,
        4u);
    EXPECT_EQ(fromText(MeshFormat::Ply, binaryPly + "\n").faceCount, 6u);
}

TEST(MeshIO, ReadsFilesByExtensionAndNamesThemInErrors) {
    TempDir dir;
    {
        std::ofstream(dir / "cube.OFF") << kCubeOff;
        std::ofstream(dir / "cube.stl", std::ios::binary) << cubeBinaryStl();
        std::ofstream(dir / "cube.txt") << kCubeOff;
    }
    EXPECT_EQ(readMesh(dir / "cube.OFF").faceCount, 6u);
    EXPECT_EQ(readMesh(dir / "cube.stl").faceCount, 12u);
    EXPECT_THROW(readMesh(dir / "cube.txt"), InputError);
    try {
        readMesh(dir / "missing.obj");
        ADD_FAILURE() << "missing file accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("missing.obj"), std::string::npos);
    }
}

TEST(MeshIO, WriteOffKeepsPolygonsAndExactCoordinates) {
    TriangleMesh mesh = fromText(MeshFormat::Off,
                                 "OFF 6 3 0\n0.1 0.2 0.3\n1 0 0\n2 1 0\n1 2 0\n0 1 0\n5 5 1e-17\n"
                                 "5 0 1 2 3 4\n3 0 1 5\n4 1 2 5 0\n");
    mesh.vertices[0] = {1.0 / 3.0, -2.0 / 7.0, 1e300};
    TempDir dir;
    writeOff(dir / "out.off", mesh);
    expectSameMesh(mesh, readMesh(dir / "out.off"));
}

TEST(MeshIO, FaceAreasSumTheTrianglesOfEachFace) {
    const std::vector<double> areas = faceAreas(fromText(MeshFormat::Off, kCubeOff));
    ASSERT_EQ(areas.size(), 6u);
    for (double area : areas) EXPECT_NEAR(area, 4.0, 1e-12);
}

TEST(MeshCheck, ClosedOpenSplitAndDegenerateCubes) {
    const TriangleMesh cube = fromText(MeshFormat::Off, kCubeOff);
    MeshDiagnostics d = checkMesh(cube);
    EXPECT_TRUE(d.closed);
    EXPECT_EQ(d.boundaryEdges, 0u);
    EXPECT_EQ(d.nonManifoldEdges, 0u);
    EXPECT_EQ(d.pieces, 1u);
    EXPECT_EQ(d.degenerateFaces, 0u);
    EXPECT_TRUE(meshWarnings(d, "cube.off").empty());

    // Without its last quad: the 4 edges around the hole are boundary edges.
    TriangleMesh open = cube;
    open.triangles.resize(10);
    open.triangleFace.resize(10);
    open.faceCount = 5;
    d = checkMesh(open);
    EXPECT_FALSE(d.closed);
    EXPECT_EQ(d.boundaryEdges, 4u);
    const auto warnings = meshWarnings(d, "hand.off");
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0],
              "hand.off: mesh is not closed (4 boundary edges); the inside is estimated");

    // Two disjoint cubes.
    TriangleMesh two = cube;
    for (const auto& v : cube.vertices) two.vertices.push_back({v[0] + 5, v[1], v[2]});
    for (std::size_t t = 0; t < cube.triangles.size(); ++t) {
        auto triangle = cube.triangles[t];
        for (auto& index : triangle) index += 8;
        two.triangles.push_back(triangle);
        two.triangleFace.push_back(cube.triangleFace[t] + 6);
    }
    two.faceCount = 12;
    d = checkMesh(two);
    EXPECT_TRUE(d.closed);
    EXPECT_EQ(d.pieces, 2u);
    EXPECT_EQ(meshWarnings(d, "two.off").size(), 1u);

    // A face with a repeated vertex has zero area.
    TriangleMesh degenerate = cube;
    degenerate.triangles.push_back({0, 1, 1});
    degenerate.triangleFace.push_back(6);
    degenerate.faceCount = 7;
    d = checkMesh(degenerate);
    EXPECT_EQ(d.degenerateFaces, 1u);
    EXPECT_EQ(d.pieces, 1u);

    // Duplicated vertices (a writer's seams) still make a closed surface.
    TriangleMesh seams = cube;
    seams.vertices.push_back(cube.vertices[0]);
    seams.triangles[0][0] = 8;
    EXPECT_TRUE(checkMesh(seams).closed);
}

TEST(MeshIO, PrincetonModelMatchesItsSegFiles) {
    if (!test::hasSharedData())
        GTEST_SKIP() << "shared data folder " << test::sharedDataDir() << " is absent";
    const auto meshPath = test::sharedDataDir() / "psb" / "off" / "1.off";
    const auto segDir = test::sharedDataDir() / "psb" / "seg" / "1";
    if (!std::filesystem::exists(meshPath) || !std::filesystem::is_directory(segDir))
        GTEST_SKIP() << "psb model 1 is absent";
    const TriangleMesh mesh = readMesh(meshPath);
    EXPECT_GT(mesh.faceCount, 1000u);
    EXPECT_EQ(mesh.triangles.size(), mesh.faceCount);  // PSB meshes are triangles
    EXPECT_TRUE(checkMesh(mesh).closed);
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(segDir)) {
        EXPECT_EQ(readSeg(entry.path()).size(), mesh.faceCount) << entry.path();
        ++files;
    }
    EXPECT_GE(files, 1);
}

}  // namespace
TEST(MeshIO, ByteOrderMarkIsSkippedInEveryTextFormat) {
    const std::string bom = "\xEF\xBB\xBF";
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nf 1 2 3\n";
    const std::string stl =
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
        "endloop\nendfacet\nendsolid t\n";
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const std::pair<MeshFormat, std::string> files[] = {{MeshFormat::Off, kCubeOff},
                                                        {MeshFormat::Obj, obj},
                                                        {MeshFormat::Stl, stl},
                                                        {MeshFormat::Ply, ply}};
    for (const auto& [format, text] : files) {
        SCOPED_TRACE(meshFormatName(format));
        const TriangleMesh plain = fromText(format, text);
        const TriangleMesh marked = fromText(format, bom + text);
        EXPECT_EQ(marked.vertices, plain.vertices);
        EXPECT_EQ(marked.triangles, plain.triangles);
        EXPECT_EQ(marked.faceCount, plain.faceCount);
    }
    const std::string seg = bom + "3\n4\n";
    EXPECT_EQ(
        readSegFromMemory("a.seg", reinterpret_cast<const std::uint8_t*>(seg.data()), seg.size()),
        (std::vector<std::int64_t>{3, 4}));
}

}  // namespace skelseg
