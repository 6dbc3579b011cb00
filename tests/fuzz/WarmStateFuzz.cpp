// Fuzz target: an optimization's warm-start state file (io::readWarmState) through a file. A
// damaged file must read as no state; the count it states must never be allocated unchecked.
#include "FuzzInput.h"
#include "common/Error.h"
#include "io/FlowFiles.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)aero::io::readWarmState(aero::fuzz::inputFile(data, size, ".state"));
    } catch (const aero::Error&) {
    }
    return 0;
}
