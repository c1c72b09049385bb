// libFuzzer target: the OFF reader (io/mesh/MeshIO.h). Seeds:
// tests/fuzz/corpus/off/.
#include "io/mesh/MeshIO.h"
#include "tests/fuzz/FuzzMesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    skelseg::fuzz::readMeshChecked(skelseg::MeshFormat::Off, data, size);
    return 0;
}
