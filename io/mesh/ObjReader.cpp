#include "io/mesh/ObjReader.h"

#include <vector>

#include "io/files/ForeignContent.h"
#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "io/mesh/MeshBuilder.h"
#include "kernels/base/Error.h"

namespace skelseg {

namespace {

/// Whether `rest`, what follows a face vertex's position index, is "",
/// "/vt", "//vn" or "/vt/vn", each index an integer or left empty: the
/// indices are not read, but "1/zz/qq" is no vertex of a face (it was taken
/// as vertex 1).
bool isTextureAndNormalPart(std::string_view rest) {
    if (rest.empty()) return true;
    if (rest.front() != '/') return false;
    rest.remove_prefix(1);
    const std::size_t slash = rest.find('/');
    const std::string_view texture = rest.substr(0, slash);
    const std::string_view normal =
        slash == std::string_view::npos ? std::string_view() : rest.substr(slash + 1);
    std::int64_t index = 0;
    return (texture.empty() || parseInteger(texture, index)) &&
           (normal.empty() || parseInteger(normal, index));
}

/// Removes a final backslash (and the blanks around it) from `line`; false
/// when the line has none. The OBJ format continues a statement on the next
/// line after one: exporters wrap long faces that way.
bool stripContinuation(std::string_view& line) {
    std::size_t end = line.size();
    while (end > 0 && isBlank(line[end - 1])) --end;
    if (end == 0 || line[end - 1] != '\\') return false;
    line = line.substr(0, end - 1);
    return true;
}

/// "v" or "f" when `keyword` is that statement with a non-ASCII byte glued
/// to it ("v" and a non-breaking space, copied from a web page), empty
/// otherwise. Skipped as an unknown statement, such a vertex shifted every
/// vertex after it: an index error lines later, or with relative indices
/// another mesh.
std::string_view gluedVertexOrFace(std::string_view keyword) {
    for (std::string_view statement : {"v", "fo", "f"})
        if (keyword.size() > statement.size() && keyword.substr(0, statement.size()) == statement &&
            static_cast<unsigned char>(keyword[statement.size()]) >= 0x80)
            return statement;
    return {};
}

}  // namespace

TriangleMesh readObj(const std::string& name, const char* data, std::size_t size) {
    MeshBuilder builder(name, 1);
    const std::size_t bom = textContentStart(name, std::string_view(data, size));
    TextTokenizer lines(data + bom, size - bom);
    std::string_view line;
    std::string joined;  // a statement continued over several lines
    std::vector<std::int64_t> polygon;
    while (lines.nextSignificantLine(line)) {
        // Messages name the line the statement starts on.
        const std::size_t lineNumber = lines.lineNumber();
        if (stripContinuation(line)) {
            joined.assign(line);
            std::string_view next;
            bool continues = true;
            while (continues && lines.nextLine(next, true)) {
                continues = stripContinuation(next);
                joined += ' ';
                joined.append(next);
            }
            line = joined;
        }
        TextTokenizer tokens(line);
        const std::string_view keyword = tokens.nextToken();
        if (keyword == "v") {
            double xyz[3];
            for (double& coordinate : xyz) {
                const std::string_view token = tokens.nextToken();
                if (!parseReal(token, coordinate))
                    builder.fail("line " + std::to_string(lineNumber) +
                                 (token.empty() ? ": vertex has fewer than 3 coordinates"
                                                : ": bad vertex coordinate " + quote(token)));
            }
            builder.addVertex(xyz[0], xyz[1], xyz[2]);
        } else if (keyword == "f" || keyword == "fo") {
            polygon.clear();
            for (std::string_view token = tokens.nextToken(); !token.empty();
                 token = tokens.nextToken()) {
                // v, v/vt, v//vn or v/vt/vn: only the position index matters.
                const std::string_view vertexPart = token.substr(0, token.find('/'));
                std::int64_t index = 0;
                if (!parseInteger(vertexPart, index) || index == 0 ||
                    !isTextureAndNormalPart(token.substr(vertexPart.size())))
                    builder.fail("line " + std::to_string(lineNumber) + ": bad face vertex " +
                                 quote(token));
                if (index < 0) {
                    // Negative: relative to the vertices defined so far.
                    const std::int64_t resolved = std::int64_t(builder.vertexCount()) + index;
                    if (resolved < 0)
                        builder.fail("line " + std::to_string(lineNumber) + ": face " +
                                     std::to_string(builder.faceCount()) + " references vertex " +
                                     std::to_string(index) + " but only " +
                                     std::to_string(builder.vertexCount()) +
                                     " vertices precede it");
                    polygon.push_back(resolved);
                } else {
                    polygon.push_back(index - 1);
                }
            }
            if (polygon.size() < 3)
                builder.fail("line " + std::to_string(lineNumber) + ": face " +
                             std::to_string(builder.faceCount()) + " has " +
                             std::to_string(polygon.size()) + " vertices; a face needs at least 3");
            builder.addFace(polygon,
                            kCheckLater);  // positive indices may point forward: checked at the end
        } else if (const std::string_view statement = gluedVertexOrFace(keyword);
                   !statement.empty()) {
            builder.fail("line " + std::to_string(lineNumber) + ": " + quote(keyword) +
                         " is no statement: a character that is not a space or tab follows '" +
                         std::string(statement) + "' (a non-breaking space?)");
        }
        // Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, ...) is ignored.
    }
    // An OBJ reader skips every statement it does not know, so any other
    // text is an OBJ file of no faces: say what it is instead.
    if (builder.faceCount() == 0) refuseForeignContent(name, std::string_view(data, size), "OBJ");
    return builder.finish();
}

}  // namespace skelseg
