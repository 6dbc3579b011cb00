// Fuzz target: the flow restart reader (io/FlowFiles.h) through a file, for a fixed two-block
// layout of 5x6x3 and 4x5x2 nodes (the seeds in corpus/restart were written for it by
// tests/io/FlowFilesTest.cpp; samples.restart is of version 2, with the grid parameters).
#include "FuzzInput.h"
#include "common/Error.h"
#include "io/FlowFiles.h"

namespace {

const aero::flow::FlowMesh& layout() {
    static const aero::flow::FlowMesh fm = [] {
        std::vector<aero::flow::FlowBlock> blocks(2);
        blocks[0].name = "a";
        blocks[0].dims = {5, 6, 3};
        blocks[1].name = "b";
        blocks[1].dims = {4, 5, 2};
        return aero::flow::makeFlowMesh(blocks, {});
    }();
    return fm;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        aero::io::RestartInfo info;
        (void)aero::io::readRestart(aero::fuzz::inputFile(data, size, ".restart"), layout(), &info);
    } catch (const aero::Error&) {
    }
    return 0;
}
