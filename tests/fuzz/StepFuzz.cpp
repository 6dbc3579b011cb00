// Fuzz target: the STEP reader (OpenCASCADE's translator) through a file.
#include "FuzzInput.h"
#include "cad/Step.h"
#include "cad/OcctProcess.h"
#include "common/Error.h"

// OpenCASCADE in this process, not in its helper: the fuzzer must see its crashes and hangs.
static const bool occtHere = (aero::cad::setOcctIsolation(aero::cad::OcctIsolation::InProcess), true);

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        aero::cad::ReadReport report;
        (void)aero::cad::readStep(aero::fuzz::inputFile(data, size, ".stp"), &report);
    } catch (const aero::Error&) {
    }
    return 0;
}
