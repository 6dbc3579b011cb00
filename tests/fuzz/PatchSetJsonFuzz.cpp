// Fuzz target: the JSON patch-set reader, in memory (io/PatchSetJson.h).
#include "FuzzInput.h"
#include "common/Error.h"
#include "io/PatchSetJson.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)aero::io::parsePatchSetJson(aero::fuzz::text(data, size), "fuzz.json");
    } catch (const aero::Error&) {
    }
    return 0;
}
