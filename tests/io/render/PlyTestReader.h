// A minimal PLY reader for the tests: ascii and binary_little_endian, scalar
// and list properties, every value as double. Independent of the writers so
// that a test checks the bytes, not the writer against itself.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace skelseg::test {

struct PlyProperty {
    std::string name, type;  // type of the value (of the items for a list)
    bool isList = false;
    std::string countType;  // list length type
};

struct PlyElement {
    std::string name;
    std::size_t count = 0;
    std::vector<PlyProperty> properties;
    /// rows[i][p]: values of property p of item i (one value for a scalar).
    std::vector<std::vector<std::vector<double>>> rows;

    int propertyIndex(const std::string& propertyName) const {
        for (std::size_t p = 0; p < properties.size(); ++p)
            if (properties[p].name == propertyName) return int(p);
        return -1;
    }
    double value(std::size_t item, const std::string& propertyName) const {
        const int p = propertyIndex(propertyName);
        if (p < 0) throw std::runtime_error("no property " + propertyName + " in " + name);
        return rows.at(item).at(std::size_t(p)).at(0);
    }
    const std::vector<double>& list(std::size_t item, const std::string& propertyName) const {
        const int p = propertyIndex(propertyName);
        if (p < 0) throw std::runtime_error("no property " + propertyName + " in " + name);
        return rows.at(item).at(std::size_t(p));
    }
};

struct PlyFile {
    std::string format;
    std::vector<std::string> comments;
    std::vector<PlyElement> elements;

    const PlyElement& element(const std::string& name) const {
        for (const auto& e : elements)
            if (e.name == name) return e;
        throw std::runtime_error("no element " + name);
    }
    bool hasElement(const std::string& name) const {
        for (const auto& e : elements)
            if (e.name == name) return true;
        return false;
    }
};

inline std::size_t plyTypeSize(const std::string& type) {
    static const std::map<std::string, std::size_t> sizes = {
        {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
        {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
        {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
    const auto it = sizes.find(type);
    if (it == sizes.end()) throw std::runtime_error("unknown PLY type " + type);
    return it->second;
}

/// How one PLY type's little-endian bytes become a value (the tests run on
/// little-endian hosts; the writer composes bytes explicitly). Resolved once
/// per property: the tests read meshes of a hundred thousand faces, under the
/// sanitizers too.
struct PlyDecoder {
    enum class Kind { Unsigned, Signed, Float, Double } kind = Kind::Unsigned;
    std::size_t size = 0;

    PlyDecoder() = default;
    explicit PlyDecoder(const std::string& type) : size(plyTypeSize(type)) {
        if (type == "float" || type == "float32")
            kind = Kind::Float;
        else if (type == "double" || type == "float64")
            kind = Kind::Double;
        else if (type == "char" || type == "int8" || type == "short" || type == "int16" ||
                 type == "int" || type == "int32")
            kind = Kind::Signed;
    }
    double decode(const unsigned char* bytes) const {
        std::uint64_t raw = 0;
        for (std::size_t b = 0; b < size; ++b) raw |= std::uint64_t(bytes[b]) << (8 * b);
        switch (kind) {
            case Kind::Float: {
                const std::uint32_t bits = std::uint32_t(raw);
                float value;
                std::memcpy(&value, &bits, 4);
                return double(value);
            }
            case Kind::Double: {
                double value;
                std::memcpy(&value, &raw, 8);
                return value;
            }
            case Kind::Signed: {
                const std::uint64_t signBit = std::uint64_t(1) << (8 * size - 1);
                return (raw & signBit) ? double(std::int64_t(raw) - std::int64_t(signBit << 1))
                                       : double(raw);
            }
            case Kind::Unsigned:
                break;
        }
        return double(raw);
    }
};

/// Reads a whole PLY file; throws std::runtime_error on anything malformed,
/// including bytes left over after the last element.
inline PlyFile readPly(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path.string());
    std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t headerEnd = content.find("end_header\n");
    if (content.rfind("ply\n", 0) != 0 || headerEnd == std::string::npos)
        throw std::runtime_error("not a PLY file");
    PlyFile ply;
    std::istringstream header(content.substr(0, headerEnd));
    std::string line;
    while (std::getline(header, line)) {
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "format") {
            words >> ply.format;
        } else if (keyword == "comment") {
            ply.comments.push_back(line.substr(8));
        } else if (keyword == "element") {
            PlyElement element;
            words >> element.name >> element.count;
            ply.elements.push_back(element);
        } else if (keyword == "property") {
            if (ply.elements.empty()) throw std::runtime_error("property before element");
            PlyProperty property;
            std::string type;
            words >> type;
            if (type == "list") {
                property.isList = true;
                words >> property.countType >> property.type >> property.name;
            } else {
                property.type = type;
                words >> property.name;
            }
            ply.elements.back().properties.push_back(property);
        }
    }
    std::size_t offset = headerEnd + std::strlen("end_header\n");
    if (ply.format == "ascii") {
        std::istringstream body(content.substr(offset));
        for (auto& element : ply.elements)
            for (std::size_t i = 0; i < element.count; ++i) {
                std::vector<std::vector<double>> row;
                for (const auto& property : element.properties) {
                    std::size_t n = 1;
                    if (property.isList) body >> n;
                    std::vector<double> values(n);
                    for (double& v : values) body >> v;
                    row.push_back(values);
                }
                if (!body) throw std::runtime_error("ascii body too short");
                element.rows.push_back(row);
            }
        return ply;
    }
    if (ply.format != "binary_little_endian")
        throw std::runtime_error("unsupported format " + ply.format);
    const auto* bytes = reinterpret_cast<const unsigned char*>(content.data());
    auto take = [&](const PlyDecoder& decoder) {
        if (offset + decoder.size > content.size())
            throw std::runtime_error("binary body too short");
        const double value = decoder.decode(bytes + offset);
        offset += decoder.size;
        return value;
    };
    for (auto& element : ply.elements) {
        std::vector<PlyDecoder> values, counts;
        for (const auto& property : element.properties) {
            values.emplace_back(property.type);
            counts.push_back(property.isList ? PlyDecoder(property.countType) : PlyDecoder());
        }
        for (std::size_t i = 0; i < element.count; ++i) {
            // Grown row by row: a count the body does not hold fails on the
            // bytes, not on the memory it claims.
            auto& row = element.rows.emplace_back(element.properties.size());
            for (std::size_t p = 0; p < element.properties.size(); ++p) {
                std::size_t n = 1;
                if (element.properties[p].isList) n = std::size_t(take(counts[p]));
                row[p].resize(n);
                for (double& v : row[p]) v = take(values[p]);
            }
        }
    }
    if (offset != content.size()) throw std::runtime_error("bytes after the last element");
    return ply;
}

}  // namespace skelseg::test
