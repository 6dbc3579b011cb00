// Fuzz target: the whole IGES reader (our parser, then OpenCASCADE for surfaces other than 128
// and 144) through a file, as `aeroform` opens one.
#include "FuzzInput.h"
#include "cad/Iges.h"
#include "cad/OcctProcess.h"
#include "common/Error.h"

// OpenCASCADE in this process, not in its helper: the fuzzer must see its crashes and hangs.
static const bool occtHere = (aero::cad::setOcctIsolation(aero::cad::OcctIsolation::InProcess), true);

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        aero::cad::ReadReport report;
        (void)aero::cad::readIges(aero::fuzz::inputFile(data, size, ".igs"), &report);
    } catch (const aero::Error&) {
    }
    return 0;
}
