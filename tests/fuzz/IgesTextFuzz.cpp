// Fuzz target: our IGES text parser and its checks, the pre-check run before OpenCASCADE sees a
// file (cad/IgesText.h), in memory.
#include "FuzzInput.h"
#include "cad/IgesText.h"
#include "common/Error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace aero::cad;
    try {
        const iges::File f = iges::parse(aero::fuzz::text(data, size), "fuzz.igs");
        for (const iges::Entity& e : f.entities) {
            iges::check(f, e);
            (void)iges::geometryChildren(f, e);
        }
        iges::checkCycles(f);
    } catch (const aero::Error&) {
    }
    return 0;
}
