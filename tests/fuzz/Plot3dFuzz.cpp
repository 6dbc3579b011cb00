// Fuzz target: the Plot3D grid reader, binary and formatted (detected from the first bytes),
// through a file (mesh/Plot3d.h).
#include "FuzzInput.h"
#include "common/Error.h"
#include "mesh/Plot3d.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)aero::mesh::readPlot3d(aero::fuzz::inputFile(data, size, ".xyz"));
    } catch (const aero::Error&) {
    }
    return 0;
}
