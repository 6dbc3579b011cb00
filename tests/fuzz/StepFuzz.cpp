// Fuzz target: the STEP reader (OpenCASCADE's translator) through a file.
#include "FuzzInput.h"
#include "cad/Step.h"
#include "common/Error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        aero::cad::ReadReport report;
        (void)aero::cad::readStep(aero::fuzz::inputFile(data, size, ".stp"), &report);
    } catch (const aero::Error&) {
    }
    return 0;
}
