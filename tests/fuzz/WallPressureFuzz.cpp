// Fuzz target: the wall-pressure CSV reader (io/FlowFiles.h; an inverse design's target) through
// a file, for the layout of tests/io/FlowFilesTest.cpp that wrote the seeds: 5x6x3 and 4x5x2
// nodes, the second block's face 4 a wall.
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
        blocks[1].faces[4].kind = aero::mesh::BoundaryKind::Wall;
        return aero::flow::makeFlowMesh(blocks, {});
    }();
    return fm;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)aero::io::readWallPressureCsv(aero::fuzz::inputFile(data, size, ".csv"), layout());
    } catch (const aero::Error&) {
    }
    return 0;
}
