#include "io/mesh/PlyReader.h"

#include <algorithm>
#include <cstring>
#include <string_view>
#include <vector>

#include "io/files/ForeignContent.h"
#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "io/mesh/MeshBuilder.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool plyTypeFromName(std::string_view name, PlyType& type) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
        {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
        {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
        {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64}};
    for (const auto& entry : names)
        if (name == entry.first) {
            type = entry.second;
            return true;
        }
    return false;
}

std::size_t plyTypeSize(PlyType type) noexcept {
    switch (type) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
    }
    return 1;
}

bool plyTypeIsInteger(PlyType type) noexcept {
    return type != PlyType::Float32 && type != PlyType::Float64;
}

struct PlyProperty {
    std::string name;
    bool isList = false;
    PlyType countType = PlyType::UInt8;  // lists only
    PlyType valueType = PlyType::Float32;
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

/// Reads PLY values one at a time from the data section, in either encoding.
class PlyValueReader {
public:
    /// headerLines: the lines before `data`, for the line numbers of ASCII messages.
    PlyValueReader(MeshBuilder& builder, PlyEncoding encoding, const std::uint8_t* data,
                   std::size_t size, std::size_t headerLines)
        : mBuilder(builder),
          mEncoding(encoding),
          mHeaderLines(headerLines),
          mData(data),
          mSize(size),
          mTokens(reinterpret_cast<const char*>(data), size) {}

    std::size_t bytesLeft() const noexcept {
        return mEncoding == PlyEncoding::Ascii ? mTokens.bytesLeft() : mSize - mPosition;
    }

    /// True when anything but whitespace follows the values read so far.
    bool dataLeft() const noexcept {
        const char* rest = reinterpret_cast<const char*>(mData) + (mSize - bytesLeft());
        return !std::all_of(rest, rest + bytesLeft(), isSpace);
    }

    /// ASCII: the line of the next token, counted from the start of the data (1-based).
    std::size_t lineOfNextToken() {
        mTokens.nextToken();
        return mTokens.lineNumber();
    }

    double readReal(PlyType type, const char* what) {
        if (mEncoding == PlyEncoding::Ascii) {
            const std::string_view token = nextToken(what);
            double value = 0;
            if (!parseReal(token, value)) badValue(what, token);
            return value;
        }
        return readBinary(type, what);
    }

    std::int64_t readInteger(PlyType type, const char* what) {
        if (mEncoding == PlyEncoding::Ascii) {
            const std::string_view token = nextToken(what);
            std::int64_t value = 0;
            if (!parseInteger(token, value)) badValue(what, token);
            return value;
        }
        return std::int64_t(readBinary(type, what));
    }

    /// Ends an item (one vertex, face, ...). ASCII: the values left on the
    /// line of its last value are ignored, as the PLY reference reader (ply.c,
    /// which reads an item per line) does; writers add undeclared values there
    /// (MeshLab's fuze_ascii.ply in trimesh's models holds 6 more per face).
    void endItem() noexcept {
        if (mEncoding == PlyEncoding::Ascii && mValuesInItem) mTokens.skipLine();
        mValuesInItem = false;
    }

    /// Skips one property value of any kind.
    void skip(PlyType type, const char* what) {
        if (mEncoding == PlyEncoding::Ascii) {
            nextToken(what);
            return;
        }
        const std::size_t bytes = plyTypeSize(type);
        if (mSize - mPosition < bytes) truncated(what);
        mPosition += bytes;
    }

private:
    [[noreturn]] void badValue(const char* what, std::string_view token) const {
        mBuilder.fail("line " + std::to_string(mHeaderLines + mTokens.lineNumber()) + ": bad " +
                      what + " value " + quote(token));
    }

    [[noreturn]] void truncated(const char* what) const {
        mBuilder.fail(std::string("file ends inside the ") + what + " data");
    }

    std::string_view nextToken(const char* what) {
        mValuesInItem = true;
        const std::string_view token = mTokens.nextToken();
        if (token.empty()) truncated(what);
        return token;
    }

    double readBinary(PlyType type, const char* what) {
        const std::size_t bytes = plyTypeSize(type);
        if (mSize - mPosition < bytes) truncated(what);
        std::uint8_t raw[8];
        std::memcpy(raw, mData + mPosition, bytes);
        mPosition += bytes;
        if (mEncoding == PlyEncoding::BinaryBigEndian)
            std::reverse(raw, raw + bytes);  // host is little-endian
        switch (type) {
            case PlyType::Int8:
                return double(std::int8_t(raw[0]));
            case PlyType::UInt8:
                return double(raw[0]);
            case PlyType::Int16: {
                std::int16_t v;
                std::memcpy(&v, raw, 2);
                return double(v);
            }
            case PlyType::UInt16: {
                std::uint16_t v;
                std::memcpy(&v, raw, 2);
                return double(v);
            }
            case PlyType::Int32: {
                std::int32_t v;
                std::memcpy(&v, raw, 4);
                return double(v);
            }
            case PlyType::UInt32: {
                std::uint32_t v;
                std::memcpy(&v, raw, 4);
                return double(v);
            }
            case PlyType::Float32: {
                float v;
                std::memcpy(&v, raw, 4);
                return double(v);
            }
            case PlyType::Float64: {
                double v;
                std::memcpy(&v, raw, 8);
                return v;
            }
        }
        return 0.0;
    }

    MeshBuilder& mBuilder;
    PlyEncoding mEncoding;
    std::size_t mHeaderLines;
    const std::uint8_t* mData;
    std::size_t mSize;
    std::size_t mPosition = 0;
    TextTokenizer mTokens;
    bool mValuesInItem = false;
};

static_assert(sizeof(float) == 4 && sizeof(double) == 8, "IEEE floats expected");

}  // namespace

TriangleMesh readPly(const std::string& name, const std::uint8_t* data, std::size_t size) {
    MeshBuilder builder(name, 0);
    const std::size_t bom =
        textContentStart(name, std::string_view(reinterpret_cast<const char*>(data), size));
    data += bom;
    size -= bom;
    TextTokenizer lines(reinterpret_cast<const char*>(data), size);
    std::string_view line;
    if (!lines.nextLine(line, false) || (line != "ply" && line != "ply\r")) {
        refuseForeignContent(name, std::string_view(reinterpret_cast<const char*>(data), size),
                             "PLY");
        builder.fail("not a PLY file (no 'ply' line)");
    }

    PlyEncoding encoding = PlyEncoding::Ascii;
    bool haveFormat = false;
    std::vector<PlyElement> elements;
    for (;;) {
        if (!lines.nextLine(line, false))
            builder.fail("file ends inside the header (no 'end_header')");
        TextTokenizer tokens(line);
        const std::string_view keyword = tokens.nextToken();
        const std::string where = "header line " + std::to_string(lines.lineNumber()) + ": ";
        if (keyword == "end_header") break;
        if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "format") {
            const std::string_view format = tokens.nextToken();
            if (format == "ascii")
                encoding = PlyEncoding::Ascii;
            else if (format == "binary_little_endian")
                encoding = PlyEncoding::BinaryLittleEndian;
            else if (format == "binary_big_endian")
                encoding = PlyEncoding::BinaryBigEndian;
            else
                builder.fail(where + "unknown format " + quote(format));
            haveFormat = true;
        } else if (keyword == "element") {
            PlyElement element;
            element.name = std::string(tokens.nextToken());
            const std::string_view countToken = tokens.nextToken();
            std::int64_t count = 0;
            if (element.name.empty() || !parseInteger(countToken, count) || count < 0)
                builder.fail(where + "bad element line");
            element.count = std::uint64_t(count);
            elements.push_back(std::move(element));
        } else if (keyword == "property") {
            if (elements.empty()) builder.fail(where + "property before any element");
            PlyProperty property;
            std::string_view typeName = tokens.nextToken();
            if (typeName == "list") {
                property.isList = true;
                if (!plyTypeFromName(tokens.nextToken(), property.countType) ||
                    !plyTypeIsInteger(property.countType))
                    builder.fail(where + "bad list count type");
                typeName = tokens.nextToken();
            }
            if (!plyTypeFromName(typeName, property.valueType))
                builder.fail(where + "unknown property type " + quote(typeName));
            property.name = std::string(tokens.nextToken());
            if (property.name.empty()) builder.fail(where + "property without a name");
            elements.back().properties.push_back(std::move(property));
        }
        // Other lines are ignored, as the PLY reference reader (ply.c) does:
        // Blender 2.4x wrote its "Created by Blender3D ..." line without
        // "comment" (assimp's Wuson.ply). An ignored line cannot go unnoticed
        // where it matters: a missing x, y, z or face list is refused, and
        // binary data that no longer matches the properties ends early or
        // leaves bytes over.
    }
    if (!haveFormat) builder.fail("the header has no 'format' line");

    const std::size_t headerLines = lines.lineNumber();
    const std::size_t dataOffset = size - lines.bytesLeft();
    PlyValueReader reader(builder, encoding, data + dataOffset, size - dataOffset, headerLines);

    // Refuse counts the data section cannot hold before allocating anything:
    // each item needs at least its fixed-size part (binary) or one character
    // and a separator per property (ASCII).
    {
        std::uint64_t available =
            std::uint64_t(reader.bytesLeft()) + 1;  // the last ASCII value needs no separator
        for (const PlyElement& element : elements) {
            std::uint64_t perItem = 0;
            for (const PlyProperty& property : element.properties)
                perItem +=
                    encoding == PlyEncoding::Ascii
                        ? 2
                        : plyTypeSize(property.isList ? property.countType : property.valueType);
            if (element.count > kMaxElementCount ||
                (perItem > 0 && element.count > available / perItem))
                builder.fail("element " + quote(std::string_view(element.name)) + " claims " +
                             std::to_string(element.count) + " items but the file has only " +
                             std::to_string(reader.bytesLeft()) + " bytes of data");
            available -= perItem * element.count;
        }
    }

    // Faces are checked against the declared vertex count (0 without a vertex
    // element), so the vertex element may come before or after the faces.
    std::uint64_t declaredVertices = 0;
    bool haveFaceElement = false;
    for (const PlyElement& element : elements)
        if (element.name == "vertex") declaredVertices += element.count;

    std::vector<std::int64_t> polygon;
    // Reads every item of a face-like element into `polygon` (its
    // 'vertex_indices' list; other properties skipped) and calls onItem.
    auto readIndexLists = [&](const PlyElement& element, auto&& onItem) {
        const std::string what = element.name;
        int indexProperty = -1;
        for (std::size_t p = 0; p < element.properties.size(); ++p) {
            const PlyProperty& property = element.properties[p];
            if (property.isList &&
                (property.name == "vertex_indices" || property.name == "vertex_index"))
                indexProperty = int(p);
        }
        if (indexProperty < 0)
            builder.fail("the " + what + " element has no 'vertex_indices' list");
        if (!plyTypeIsInteger(element.properties[std::size_t(indexProperty)].valueType))
            builder.fail(what + " vertex indices are not integers");
        // Only now: the size check bounds the count of an element with a
        // list (a count byte per item at least), not of one without
        // properties, whose reserve took gigabytes (found by FuzzPly).
        builder.reserve(0, element.count);
        for (std::uint64_t item = 0; item < element.count; ++item) {
            for (std::size_t p = 0; p < element.properties.size(); ++p) {
                const PlyProperty& property = element.properties[p];
                if (!property.isList) {
                    reader.skip(property.valueType, what.c_str());
                    continue;
                }
                const std::int64_t count = reader.readInteger(property.countType, what.c_str());
                if (count < 0 || std::uint64_t(count) > reader.bytesLeft())
                    builder.fail(what + " " + std::to_string(item) + " has a bad list length " +
                                 std::to_string(count));
                if (int(p) != indexProperty) {
                    for (std::int64_t i = 0; i < count; ++i)
                        reader.skip(property.valueType, what.c_str());
                    continue;
                }
                polygon.clear();
                for (std::int64_t i = 0; i < count; ++i)
                    polygon.push_back(reader.readInteger(property.valueType, what.c_str()));
            }
            reader.endItem();
            onItem();
        }
    };
    for (const PlyElement& element : elements) {
        if (element.name == "vertex") {
            int axisProperty[3] = {-1, -1, -1};
            for (std::size_t p = 0; p < element.properties.size(); ++p) {
                const PlyProperty& property = element.properties[p];
                for (int axis = 0; axis < 3; ++axis)
                    if (!property.isList && property.name == std::string(1, char('x' + axis)))
                        axisProperty[axis] = int(p);
            }
            if (axisProperty[0] < 0 || axisProperty[1] < 0 || axisProperty[2] < 0)
                builder.fail("the vertex element lacks one of the properties x, y, z");
            builder.reserve(element.count, 0);
            for (std::uint64_t v = 0; v < element.count; ++v) {
                double xyz[3] = {0, 0, 0};
                for (std::size_t p = 0; p < element.properties.size(); ++p) {
                    const PlyProperty& property = element.properties[p];
                    int axis = -1;
                    for (int a = 0; a < 3; ++a)
                        if (axisProperty[a] == int(p)) axis = a;
                    if (axis >= 0) {
                        xyz[axis] = reader.readReal(property.valueType, "vertex");
                    } else if (property.isList) {
                        const std::int64_t count = reader.readInteger(property.countType, "vertex");
                        if (count < 0 || std::uint64_t(count) > reader.bytesLeft())
                            builder.fail("bad list length in vertex " + std::to_string(v));
                        for (std::int64_t i = 0; i < count; ++i)
                            reader.skip(property.valueType, "vertex");
                    } else {
                        reader.skip(property.valueType, "vertex");
                    }
                }
                reader.endItem();
                builder.addVertex(xyz[0], xyz[1], xyz[2]);
            }
        } else if (element.name == "face") {
            haveFaceElement = true;
            readIndexLists(element, [&] { builder.addFace(polygon, declaredVertices); });
        } else if (element.name == "tristrips") {
            // Triangle strips (the Stanford scanning repository's older
            // files, e.g. igea.ply): -1 starts a new strip. Each triangle of
            // a strip is one face, in strip order, every second one flipped
            // to keep the orientation; the triangles a strip repeats a vertex
            // in (to turn) are no faces.
            haveFaceElement = true;
            std::vector<std::int64_t> strip;
            readIndexLists(element, [&] {
                strip.swap(polygon);
                std::int64_t inStrip = 0;
                for (std::size_t i = 0; i < strip.size(); ++i) {
                    inStrip = strip[i] == -1 ? 0 : inStrip + 1;
                    if (inStrip < 3) continue;
                    const std::int64_t a = strip[i - 2], b = strip[i - 1], c = strip[i];
                    if (a == b || b == c || a == c) continue;
                    const bool flip = (inStrip - 3) % 2 == 1;
                    polygon.assign({flip ? b : a, flip ? a : b, c});
                    builder.addFace(polygon, declaredVertices);
                }
            });
        } else if (!element.properties.empty()) {
            // Any other element (edges, materials, ...): skip it value by
            // value. One without properties holds no data, whatever its
            // count, which the size check cannot bound (a fuzzed header
            // declared billions of empty items).
            for (std::uint64_t item = 0; item < element.count; ++item) {
                for (const PlyProperty& property : element.properties) {
                    if (!property.isList) {
                        reader.skip(property.valueType, "element");
                        continue;
                    }
                    const std::int64_t count = reader.readInteger(property.countType, "element");
                    if (count < 0 || std::uint64_t(count) > reader.bytesLeft())
                        builder.fail("element " + quote(std::string_view(element.name)) +
                                     " has a bad list length " + std::to_string(count));
                    for (std::int64_t i = 0; i < count; ++i)
                        reader.skip(property.valueType, "element");
                }
                reader.endItem();
            }
        }
    }
    if (!haveFaceElement) builder.fail("the file has no face element");
    // Whitespace may follow the last element; anything else means a count in
    // the header is wrong, and reading on would drop part of the mesh.
    if (reader.dataLeft()) {
        // The extra data follows the last element that has items; an element
        // declared with 0 items ("element face 0" of a point cloud) read none.
        const PlyElement* lastRead = &elements.back();
        for (const PlyElement& element : elements)
            if (element.count > 0) lastRead = &element;
        const std::string last = quote(std::string_view(lastRead->name));
        const std::string declared = std::to_string(lastRead->count);
        if (encoding != PlyEncoding::Ascii)
            builder.fail(std::to_string(reader.bytesLeft()) +
                         " bytes follow the last element the header declares (" + declared +
                         " items of " + last + ")");
        builder.fail("line " + std::to_string(headerLines + reader.lineOfNextToken()) +
                     ": the file holds more " + last + " lines than its header declares (" +
                     declared + ")");
    }
    return builder.finish();
}

}  // namespace skelseg
