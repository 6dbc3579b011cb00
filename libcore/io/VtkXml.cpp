#include "io/VtkXml.h"

#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <sstream>
#include <string_view>

#include "common/Error.h"

// File layout (VTK "XML file formats"): every DataArray has format="appended" and an offset
// into the <AppendedData encoding="raw"> section, counted from the byte after its leading '_'.
// At that offset: a UInt64 byte count, then the Float64 values, both little endian.

namespace aero::io {

namespace fs = std::filesystem;

namespace {

/// Characters valid in an XML 1.0 attribute; control characters (invalid in XML 1.0) become ' '.
std::string xmlEscape(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&apos;";
                break;
            default:
                out += (static_cast<unsigned char>(c) < 0x20) ? ' ' : c;
        }
    }
    return out;
}

/// A file-name-safe version of `name`: [A-Za-z0-9._-] kept, anything else '_', no leading '.'.
std::string sanitizeFileName(const std::string& name) {
    std::string out = name.empty() ? std::string("group") : name;
    for (char& c : out) {
        const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                          (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.';
        if (!keep) c = '_';
    }
    if (out.front() == '.') out.front() = '_';
    return out;
}

std::string lowercase(std::string s) {
    for (char& c : s) {
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    }
    return s;
}

std::size_t pointCount(const StructuredBlock& b) {
    return std::size_t(b.dims[0]) * std::size_t(b.dims[1]) * std::size_t(b.dims[2]);
}

std::size_t cellCount(const StructuredBlock& b) {
    std::size_t n = 1;
    for (int d : b.dims) n *= std::size_t(d > 1 ? d - 1 : 1);
    return n;
}

void checkFields(const std::vector<VtkField>& fields, std::size_t count, const char* kind,
                 const std::string& where) {
    std::set<std::string> seen;
    for (const VtkField& f : fields) {
        const std::string field = where + ", " + kind + " field '" + f.name + "'";
        if (f.name.empty()) throw Error(where + ": a " + kind + " field has no name");
        if (!seen.insert(f.name).second) throw Error(field + ": name used twice");
        if (f.components < 1) {
            throw Error(field + ": components must be at least 1, got " +
                        std::to_string(f.components));
        }
        const std::size_t nc = std::size_t(f.components);
        if (f.values.size() % nc != 0 || f.values.size() / nc != count) {
            throw Error(field + ": has " + std::to_string(f.values.size()) + " values, expected " +
                        std::to_string(nc) + " x " + std::to_string(count) + " " + kind + "s");
        }
    }
}

/// `where` names the block in messages, e.g. "VTK block 'upper' (group 'wing', index 0)".
void validate(const StructuredBlock& b, const std::string& where) {
    // dims are ints, so the extents fit VTK's int extents; 3 x their product must fit a size_t.
    std::size_t n = 1;
    for (int d : b.dims) {
        if (d < 1) {
            throw Error(where + ": dims must be at least 1, got " + std::to_string(b.dims[0]) +
                        " x " + std::to_string(b.dims[1]) + " x " + std::to_string(b.dims[2]));
        }
        if (n > std::numeric_limits<std::size_t>::max() / 3 / std::size_t(d)) {
            throw Error(where + ": dims too large");
        }
        n *= std::size_t(d);
    }
    if (b.points.size() != 3 * n) {
        throw Error(where + ", points: has " + std::to_string(b.points.size()) +
                    " values, expected 3 x " + std::to_string(n) + " points");
    }
    checkFields(b.pointData, pointCount(b), "point", where);
    checkFields(b.cellData, cellCount(b), "cell", where);
}

void requireExtension(const std::string& path, const char* ext) {
    if (fs::path(path).extension() != ext) {
        throw InputError("'" + path + "': file name must end in " + ext);
    }
}

void writeLittleEndian(std::ostream& out, const void* data, std::size_t bytes) {
    if constexpr (std::endian::native == std::endian::little) {
        out.write(static_cast<const char*>(data), std::streamsize(bytes));
    } else {
        // Every word written is 8 bytes wide (UInt64 headers, Float64 values): reverse each.
        const char* p = static_cast<const char*>(data);
        char word[8];
        for (std::size_t w = 0; w < bytes; w += 8) {
            for (int b = 0; b < 8; ++b) word[b] = p[w + 7 - b];
            out.write(word, 8);
        }
    }
}

/// Writes through `fill` into path + ".tmp", then renames it over `path`.
void writeFile(const std::string& path, const std::function<void(std::ostream&)>& fill) {
    const std::string tmp = path + ".tmp";
    auto fail = [&](const std::string& what) {
        const int err = errno;
        std::remove(tmp.c_str());
        throw InputError("cannot " + what + " VTK file '" + path + "'" +
                         (err ? std::string(": ") + std::strerror(err) : ""));
    };
    {
        errno = 0;
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) fail("write");
        fill(out);
        out.close();
        if (!out) fail("write");
    }
    errno = 0;
    if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("replace");
}

std::string extent(const StructuredBlock& b) {
    return "0 " + std::to_string(b.dims[0] - 1) + " 0 " + std::to_string(b.dims[1] - 1) + " 0 " +
           std::to_string(b.dims[2] - 1);
}

void writeStructured(const std::string& path, const StructuredBlock& b) {
    // Arrays in file order: point data, cell data, points (the order VTK's writer uses).
    std::vector<const std::vector<double>*> payloads;
    std::ostringstream xml;
    std::uint64_t offset = 0;
    auto dataArray = [&](const std::string& nameAttr, int components,
                         const std::vector<double>& values) {
        xml << "        <DataArray type=\"Float64\"" << nameAttr << " NumberOfComponents=\""
            << components << "\" format=\"appended\" offset=\"" << offset << "\"/>\n";
        offset += sizeof(std::uint64_t) + values.size() * sizeof(double);
        payloads.push_back(&values);
    };
    auto section = [&](const char* tag, const std::vector<VtkField>& fields) {
        xml << "      <" << tag << ">\n";
        for (const VtkField& f : fields)
            dataArray(" Name=\"" + xmlEscape(f.name) + "\"", f.components, f.values);
        xml << "      </" << tag << ">\n";
    };

    const std::string ext = extent(b);
    xml << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"StructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n"
        << "  <StructuredGrid WholeExtent=\"" << ext << "\">\n"
        << "    <Piece Extent=\"" << ext << "\">\n";
    section("PointData", b.pointData);
    section("CellData", b.cellData);
    xml << "      <Points>\n";
    dataArray(" Name=\"Points\"", 3, b.points);
    xml << "      </Points>\n"
        << "    </Piece>\n"
        << "  </StructuredGrid>\n"
        << "  <AppendedData encoding=\"raw\">\n   _";
    const std::string head = xml.str();

    writeFile(path, [&](std::ostream& out) {
        out << head;
        for (const std::vector<double>* values : payloads) {
            const std::uint64_t bytes = values->size() * sizeof(double);
            writeLittleEndian(out, &bytes, sizeof bytes);
            writeLittleEndian(out, values->data(), bytes);
        }
        out << "\n  </AppendedData>\n</VTKFile>\n";
    });
}

}  // namespace

void writeVts(const std::string& path, const StructuredBlock& block) {
    requireExtension(path, ".vts");
    validate(block, "VTK block '" + block.name + "'");
    writeStructured(path, block);
}

void writeVtm(const std::string& path, const std::vector<MultiBlockGroup>& groups) {
    requireExtension(path, ".vtm");
    for (const MultiBlockGroup& g : groups) {
        for (std::size_t i = 0; i < g.blocks.size(); ++i) {
            validate(g.blocks[i], "VTK block '" + g.blocks[i].name + "' (group '" + g.name +
                                      "', index " + std::to_string(i) + ")");
        }
    }

    const fs::path vtm(path);
    const std::string folderName = vtm.stem().string();
    const fs::path folder = vtm.parent_path() / folderName;
    std::error_code ec;
    fs::create_directory(folder, ec);
    if (ec || !fs::is_directory(folder)) {
        throw InputError("cannot create folder '" + folder.string() +
                         "' for VTK multiblock file '" + path + "'" +
                         (ec ? ": " + ec.message() : ": a file of that name exists"));
    }

    // File stems unique per group, compared without case (case-insensitive file systems).
    std::set<std::string> used;
    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n"
        << "  <vtkMultiBlockDataSet>\n";
    for (std::size_t gi = 0; gi < groups.size(); ++gi) {
        const MultiBlockGroup& g = groups[gi];
        const std::string base = sanitizeFileName(g.name);
        std::string stem = base;
        for (int k = 2; !used.insert(lowercase(stem)).second; ++k)
            stem = base + "-" + std::to_string(k);

        xml << "    <Block index=\"" << gi << "\" name=\"" << xmlEscape(g.name) << "\">\n";
        for (std::size_t i = 0; i < g.blocks.size(); ++i) {
            const std::string file = stem + "_" + std::to_string(i) + ".vts";
            writeStructured((folder / file).string(), g.blocks[i]);
            xml << "      <DataSet index=\"" << i << "\" name=\"" << xmlEscape(g.blocks[i].name)
                << "\" file=\"" << xmlEscape(folderName + "/" + file) << "\"/>\n";
        }
        xml << "    </Block>\n";
    }
    xml << "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
    const std::string text = xml.str();
    writeFile(path, [&](std::ostream& out) { out << text; });
}

}  // namespace aero::io
