// libFuzzer target: the PLY reader (io/mesh/MeshIO.h). Seeds:
// tests/fuzz/corpus/ply/.
#include "io/mesh/MeshIO.h"
#include "tests/fuzz/FuzzMesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    skelseg::fuzz::readMeshChecked(skelseg::MeshFormat::Ply, data, size);
    return 0;
}
