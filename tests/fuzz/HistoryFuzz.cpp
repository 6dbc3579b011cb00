// Fuzz target: the optimization history reader (JSON lines, study/Optimization.h) through a
// file, as a resumed optimization reads it.
#include "FuzzInput.h"
#include "common/Error.h"
#include "study/Optimization.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)aero::study::readHistory(aero::fuzz::inputFile(data, size, ".jsonl"));
    } catch (const aero::Error&) {
    }
    return 0;
}
