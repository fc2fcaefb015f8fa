// libFuzzer target: TetGen .node + .ele through uvr::read_tetgen. The input is the .node text, the separator UVRSPLIT,
// then the .ele text (no separator: an empty .ele). The two parts are written as input.node and input.ele.
#include "reference/dataset.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size)
{
    bool had_separator = false;
    const auto [node, ele] = uvr_fuzz::split(uvr_fuzz::as_view(data, size), had_separator);
    const std::string node_path = uvr_fuzz::write_file("input.node", node);
    uvr_fuzz::write_file("input.ele", ele);
    return uvr_fuzz::expect_input_error_only([&] { uvr::read_tetgen(node_path); });
}
