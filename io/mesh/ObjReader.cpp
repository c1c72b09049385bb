#include "io/mesh/ObjReader.h"

#include <vector>

#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "io/mesh/MeshBuilder.h"
#include "kernels/base/Error.h"

namespace skelseg {

TriangleMesh readObj(const std::string& name, const char* data, std::size_t size) {
    MeshBuilder builder(name, 1);
    const std::size_t bom = utf8BomLength(std::string_view(data, size));
    TextTokenizer lines(data + bom, size - bom);
    std::string_view line;
    std::vector<std::int64_t> polygon;
    while (lines.nextSignificantLine(line)) {
        TextTokenizer tokens(line);
        const std::string_view keyword = tokens.nextToken();
        if (keyword == "v") {
            double xyz[3];
            for (double& coordinate : xyz) {
                const std::string_view token = tokens.nextToken();
                if (!parseReal(token, coordinate))
                    builder.fail("line " + std::to_string(lines.lineNumber()) +
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
                if (!parseInteger(vertexPart, index) || index == 0)
                    builder.fail("line " + std::to_string(lines.lineNumber()) +
                                 ": bad face vertex " + quote(token));
                if (index < 0) {
                    // Negative: relative to the vertices defined so far.
                    const std::int64_t resolved = std::int64_t(builder.vertexCount()) + index;
                    if (resolved < 0)
                        builder.fail("line " + std::to_string(lines.lineNumber()) + ": face " +
                                     std::to_string(builder.faceCount()) + " references vertex " +
                                     std::to_string(index) + " but only " +
                                     std::to_string(builder.vertexCount()) +
                                     " vertices precede it");
                    polygon.push_back(resolved);
                } else {
                    polygon.push_back(index - 1);
                }
            }
            builder.addFace(polygon,
                            kCheckLater);  // positive indices may point forward: checked at the end
        }
        // Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, ...) is ignored.
    }
    return builder.finish();
}

}  // namespace skelseg
