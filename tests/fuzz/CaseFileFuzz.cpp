// Fuzz target: the case-file parser and its validation, in memory (io/CaseFile.h). Paths the
// case names (geometry, lattice files) are resolved against a directory that does not exist.
#include "FuzzInput.h"
#include "common/Error.h"
#include "io/CaseFile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)aero::io::parseCase(aero::fuzz::text(data, size), "/nonexistent/fuzz.json");
    } catch (const aero::Error&) {
    }
    return 0;
}
