#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>

#include "common/Error.h"
#include "io/VtkXml.h"

using namespace aero;
namespace fs = std::filesystem;

namespace {

std::string tempPath(const std::string& name) {
    return std::string(AEROFORM_TEST_OUTPUT_DIR) + "/" + name;
}

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    EXPECT_TRUE(in) << path;
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// Value of attribute `name` in the tag that starts at `tag` (simple search up to its '>').
std::string attribute(const std::string& text, std::size_t tag, const std::string& name) {
    const std::size_t end = text.find('>', tag);
    const std::size_t at = text.find(" " + name + "=\"", tag);
    if (at == std::string::npos || at > end) return "<missing " + name + ">";
    const std::size_t begin = at + name.size() + 3;
    return text.substr(begin, text.find('"', begin) - begin);
}

struct Array {
    std::string name;
    int components = 0;
    std::vector<double> values;
};

/// A .vts file read back by string search; arrays decoded from the appended raw section.
struct Vts {
    std::string wholeExtent, extent;
    std::vector<Array> pointData, cellData;
    Array points;
};

std::uint64_t littleEndianWord(const std::string& bytes, std::size_t at) {
    std::uint64_t w = 0;
    for (int b = 7; b >= 0; --b) w = (w << 8) | static_cast<unsigned char>(bytes.at(at + b));
    return w;
}

Vts readVts(const fs::path& path) {
    const std::string text = readFile(path);
    const std::size_t appended = text.find("<AppendedData encoding=\"raw\">");
    const std::string head = text.substr(0, appended);  // XML only: search never enters the payload
    EXPECT_NE(appended, std::string::npos);
    EXPECT_NE(head.find("<VTKFile type=\"StructuredGrid\" version=\"1.0\""), std::string::npos);
    EXPECT_EQ(attribute(head, head.find("<VTKFile"), "byte_order"), "LittleEndian");
    EXPECT_EQ(attribute(head, head.find("<VTKFile"), "header_type"), "UInt64");
    const std::size_t data = text.find('_', appended) + 1;  // offsets count from here

    auto arrays = [&](const std::string& section) {
        std::vector<Array> out;
        const std::size_t begin = head.find("<" + section + ">");
        const std::size_t end = head.find("</" + section + ">");
        EXPECT_NE(begin, std::string::npos) << section;
        for (std::size_t at = head.find("<DataArray", begin); at < end;
             at = head.find("<DataArray", at + 1)) {
            EXPECT_EQ(attribute(head, at, "type"), "Float64");
            EXPECT_EQ(attribute(head, at, "format"), "appended");
            Array a;
            a.name = attribute(head, at, "Name");
            a.components = std::stoi(attribute(head, at, "NumberOfComponents"));
            const std::size_t offset = std::stoull(attribute(head, at, "offset"));
            const std::uint64_t bytes = littleEndianWord(text, data + offset);
            EXPECT_EQ(bytes % 8, 0u);
            for (std::uint64_t b = 0; b < bytes; b += 8) {
                a.values.push_back(
                    std::bit_cast<double>(littleEndianWord(text, data + offset + 8 + b)));
            }
            out.push_back(std::move(a));
        }
        return out;
    };
    Vts v;
    v.wholeExtent = attribute(head, head.find("<StructuredGrid"), "WholeExtent");
    v.extent = attribute(head, head.find("<Piece"), "Extent");
    v.pointData = arrays("PointData");
    v.cellData = arrays("CellData");
    const std::vector<Array> points = arrays("Points");
    EXPECT_EQ(points.size(), 1u);
    if (!points.empty()) v.points = points.front();
    return v;
}

void expectBitwiseEqual(const std::vector<double>& a, const std::vector<double>& b,
                        const std::string& what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(a[i]), std::bit_cast<std::uint64_t>(b[i]))
            << what << "[" << i << "]";
    }
}

void expectSameArrays(const std::vector<Array>& read, const std::vector<io::VtkField>& written) {
    ASSERT_EQ(read.size(), written.size());
    for (std::size_t f = 0; f < read.size(); ++f) {
        EXPECT_EQ(read[f].name, written[f].name);
        EXPECT_EQ(read[f].components, written[f].components);
        expectBitwiseEqual(read[f].values, written[f].values, written[f].name);
    }
}

/// 3 x 4 x 2 points (i fastest) with values whose bits a decimal round trip would not keep,
/// a scalar point field and a 3-component field on the 2 x 3 x 1 cells.
io::StructuredBlock makeGrid() {
    io::StructuredBlock b;
    b.name = "box <1> & co";
    b.dims = {3, 4, 2};
    io::VtkField pressure{"pressure", 1, {}}, velocity{"velocity", 3, {}};
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < 4; ++j) {
            for (int i = 0; i < 3; ++i) {
                b.points.insert(b.points.end(),
                                {0.1 * i + 1.0 / 3.0, std::sqrt(2.0) * j, -std::numbers::pi * k});
                pressure.values.push_back(std::sin(i + 3.0 * j + 12.0 * k) * 1e-300);
            }
        }
    }
    pressure.values[5] = -0.0;
    pressure.values[6] = std::numeric_limits<double>::denorm_min();
    for (int c = 0; c < 2 * 3 * 1; ++c)
        velocity.values.insert(velocity.values.end(), {c / 7.0, -c / 9.0, 1e10 + c});
    b.pointData.push_back(pressure);
    b.cellData.push_back(velocity);
    return b;
}

io::StructuredBlock makeCurve() {
    io::StructuredBlock b;
    b.name = "leading edge";
    b.dims = {5, 1, 1};
    for (int i = 0; i < 5; ++i) b.points.insert(b.points.end(), {i / 4.0, 0.3 * i * i, 0.0});
    return b;
}

template <typename E>
void expectThrowsNaming(const std::function<void()>& call,
                        const std::vector<std::string>& fragments) {
    try {
        call();
        ADD_FAILURE() << "no exception";
    } catch (const E& e) {
        for (const std::string& f : fragments) {
            EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
                << "'" << f << "' not in: " << e.what();
        }
    }
}

}  // namespace

TEST(VtkXml, MultiBlockRoundTripIsExact) {
    const fs::path vtm = tempPath("vtkxml_deformed.vtm");
    fs::remove_all(tempPath("vtkxml_deformed"));
    const std::vector<io::MultiBlockGroup> groups = {{"wing box", {makeGrid()}},
                                                     {"edges/lead", {makeCurve()}}};
    io::writeVtm(vtm.string(), groups);

    const std::string text = readFile(vtm);
    EXPECT_NE(text.find("<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\""),
              std::string::npos);
    EXPECT_NE(text.find("<Block index=\"0\" name=\"wing box\">"), std::string::npos) << text;
    EXPECT_NE(text.find("<Block index=\"1\" name=\"edges/lead\">"), std::string::npos) << text;
    const std::size_t box = text.find("<DataSet index=\"0\" name=\"box &lt;1&gt; &amp; co\"");
    const std::size_t edge = text.find("<DataSet index=\"0\" name=\"leading edge\"");
    ASSERT_NE(box, std::string::npos) << text;
    ASSERT_NE(edge, std::string::npos) << text;
    EXPECT_EQ(attribute(text, box, "file"),
              "vtkxml_deformed/wing_box_0.vts");  // relative, sanitized
    EXPECT_EQ(attribute(text, edge, "file"), "vtkxml_deformed/edges_lead_0.vts");

    const io::StructuredBlock grid = makeGrid();
    const Vts g = readVts(vtm.parent_path() / attribute(text, box, "file"));
    EXPECT_EQ(g.wholeExtent, "0 2 0 3 0 1");
    EXPECT_EQ(g.extent, "0 2 0 3 0 1");
    EXPECT_EQ(g.points.components, 3);
    expectBitwiseEqual(g.points.values, grid.points, "points");
    expectSameArrays(g.pointData, grid.pointData);
    expectSameArrays(g.cellData, grid.cellData);

    const Vts c = readVts(vtm.parent_path() / attribute(text, edge, "file"));
    EXPECT_EQ(c.wholeExtent, "0 4 0 0 0 0");
    expectBitwiseEqual(c.points.values, makeCurve().points, "curve points");
    EXPECT_TRUE(c.pointData.empty());
    EXPECT_TRUE(c.cellData.empty());
}

TEST(VtkXml, SingleGridAndGroupsWithTheSameFileName) {
    const std::string vts = tempPath("vtkxml_single.vts");
    io::StructuredBlock point;  // 1 x 1 x 1: one vertex cell
    point.points = {1.0, 2.0, 3.0};
    point.cellData.push_back({"id", 1, {7.0}});
    io::writeVts(vts, point);
    const Vts v = readVts(vts);
    EXPECT_EQ(v.extent, "0 0 0 0 0 0");
    ASSERT_EQ(v.cellData.size(), 1u);
    EXPECT_EQ(v.cellData[0].values, std::vector<double>{7.0});

    // "a b", "a/b" and "A_B" all sanitize to a_b: each group keeps its own files.
    const std::string vtm = tempPath("vtkxml_clash.vtm");
    io::writeVtm(vtm, {{"a b", {point}}, {"a/b", {point}}, {"A_B", {point, point}}});
    const std::string text = readFile(vtm);
    for (const char* file : {"a_b_0.vts", "a_b-2_0.vts", "A_B-3_0.vts", "A_B-3_1.vts"}) {
        EXPECT_NE(text.find(std::string("file=\"vtkxml_clash/") + file + "\""), std::string::npos)
            << file;
        EXPECT_TRUE(fs::exists(tempPath("vtkxml_clash/") + file)) << file;
    }
}

TEST(VtkXml, InconsistentSizesThrowBeforeWriting) {
    const std::string vtm = tempPath("vtkxml_bad.vtm");
    fs::remove(vtm);
    fs::remove_all(tempPath("vtkxml_bad"));

    io::StructuredBlock badPoint = makeGrid();
    badPoint.pointData[0].values.pop_back();
    expectThrowsNaming<Error>(
        [&] {
            io::writeVtm(vtm, {{"ok", {makeCurve()}}, {"wing", {badPoint}}});
        },
        {"box <1> & co", "wing", "point field 'pressure'", "23", "24"});

    io::StructuredBlock badCell = makeGrid();
    badCell.cellData[0].components = 2;
    expectThrowsNaming<Error>(
        [&] {
            io::writeVtm(vtm, {{"wing", {badCell}}});
        },
        {"cell field 'velocity'"});

    io::StructuredBlock badPoints = makeCurve();
    badPoints.dims = {4, 1, 1};
    expectThrowsNaming<Error>([&] { io::writeVts(tempPath("vtkxml_bad.vts"), badPoints); },
                              {"leading edge", "points"});

    io::StructuredBlock badDims = makeCurve();
    badDims.dims = {5, 0, 1};
    expectThrowsNaming<Error>(
        [&] {
            io::writeVtm(vtm, {{"wing", {badDims}}});
        },
        {"leading edge", "dims"});

    EXPECT_FALSE(fs::exists(vtm));
    EXPECT_FALSE(fs::exists(tempPath("vtkxml_bad")));
    EXPECT_FALSE(fs::exists(tempPath("vtkxml_bad.vts")));
}

TEST(VtkXml, UnwritablePathThrowsInputErrorNamingIt) {
    // A regular file used as a folder cannot be written into, even by root.
    const std::string blocker = tempPath("vtkxml_blocker");
    std::ofstream(blocker) << "not a folder";
    const std::string vtm = blocker + "/out.vtm";
    expectThrowsNaming<InputError>([&] { io::writeVtm(vtm, {{"wing", {makeCurve()}}}); }, {vtm});
    const std::string vts = blocker + "/out.vts";
    expectThrowsNaming<InputError>([&] { io::writeVts(vts, makeCurve()); }, {vts});
    expectThrowsNaming<InputError>([&] { io::writeVtm(tempPath("vtkxml_wrong.vtk"), {}); },
                                   {"vtkxml_wrong.vtk", ".vtm"});
}
