#include "mesh/Plot3d.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <locale>
#include <string_view>
#include <utility>

#include "common/Error.h"

namespace aero::mesh {

namespace {

constexpr const char* kCoordName[3] = {"x", "y", "z"};
// Largest record payload a signed 4-byte marker can describe.
constexpr std::uint64_t kMaxRecord =
    static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max());

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw InputError("Plot3D file '" + path + "': " + what);
}

std::string blockName(int b) {
    return "block " + std::to_string(b);
}

// Largest block accepted: 10^9 nodes (24 GB of coordinates). Checked in floating point, so a
// product of large dims cannot wrap (16 x 2^30 x 2^30 wrapped to 0 nodes).
constexpr long kMaxBlockNodes = 1000000000L;

void checkBlockSize(const std::string& path, const std::string& name, int a, int b, int c) {
    const double n = static_cast<double>(a) * b * c;
    if (n > static_cast<double>(kMaxBlockNodes)) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%.3g", n);
        fail(path, name + ": " + std::to_string(a) + " x " + std::to_string(b) + " x " + std::to_string(c) + " = " + buf +
                       " nodes, more than the 10^9 a block may have");
    }
}

// ---- little-endian encoding -------------------------------------------------------------

std::uint32_t readLe32(const unsigned char* p) {
    return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
           static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

void writeLe32(unsigned char* p, std::uint32_t v) {
    for (int b = 0; b < 4; ++b) p[b] = static_cast<unsigned char>(v >> (8 * b));
}

// Converts n words of `Bytes` bytes in place between little-endian and the host order.
template <int Bytes>
void fromLittleEndian(void* data, std::size_t n) {
    if constexpr (std::endian::native != std::endian::little) {
        auto* p = static_cast<unsigned char*>(data);
        for (std::size_t w = 0; w < n; ++w, p += Bytes) {
            for (int b = 0; b < Bytes / 2; ++b) std::swap(p[b], p[Bytes - 1 - b]);
        }
    } else {
        (void)data;
        (void)n;
    }
}

// ---- writing ---------------------------------------------------------------------------

void checkBlockForWriting(const std::vector<StructuredGrid>& blocks, int b) {
    const StructuredGrid& g = blocks[b];
    const std::string who = "Plot3D output, block " + std::to_string(b) + " '" + g.name + "'";
    for (int d = 0; d < 3; ++d) {
        if (g.dims[d] < 1) {
            throw GeometryError(who + ": dims must be at least 1, got " +
                                std::to_string(g.dims[0]) + " x " + std::to_string(g.dims[1]) +
                                " x " + std::to_string(g.dims[2]));
        }
    }
    if (g.xyz.size() != 3 * static_cast<std::size_t>(g.nodeCount())) {
        throw GeometryError(who + ": xyz has " + std::to_string(g.xyz.size()) +
                            " values, expected 3 * " + std::to_string(g.nodeCount()));
    }
    for (std::size_t a = 0; a < g.xyz.size(); ++a) {
        if (!std::isfinite(g.xyz[a])) {
            throw GeometryError(who + ": node " + std::to_string(a / 3) + " has a non-finite " +
                                kCoordName[a % 3] + " coordinate");
        }
    }
}

void writeBinary(std::ostream& out, const std::string& path,
                 const std::vector<StructuredGrid>& blocks) {
    unsigned char word[4];
    auto marker = [&](std::uint64_t bytes) {
        writeLe32(word, static_cast<std::uint32_t>(bytes));
        out.write(reinterpret_cast<const char*>(word), 4);
    };
    auto int32 = [&](int v) {
        writeLe32(word, static_cast<std::uint32_t>(v));
        out.write(reinterpret_cast<const char*>(word), 4);
    };
    const int nb = static_cast<int>(blocks.size());
    marker(4);
    int32(nb);
    marker(4);
    const std::uint64_t dimsBytes = 12 * static_cast<std::uint64_t>(nb);
    if (dimsBytes > kMaxRecord) fail(path, "too many blocks for 4-byte record markers");
    marker(dimsBytes);
    for (const StructuredGrid& g : blocks) {
        for (int d = 0; d < 3; ++d) int32(g.dims[d]);
    }
    marker(dimsBytes);
    std::vector<unsigned char> buf;
    for (int b = 0; b < nb; ++b) {
        const StructuredGrid& g = blocks[b];
        const std::uint64_t n = static_cast<std::uint64_t>(g.nodeCount());
        const std::uint64_t bytes = 24 * n;
        if (bytes > kMaxRecord) {
            fail(path, blockName(b) + " needs a record of " + std::to_string(bytes) +
                           " bytes, over the 2 GiB limit of 4-byte record markers");
        }
        marker(bytes);
        buf.resize(8 * n);
        for (int c = 0; c < 3; ++c) {
            for (std::uint64_t a = 0; a < n; ++a) std::memcpy(&buf[8 * a], &g.xyz[3 * a + c], 8);
            fromLittleEndian<8>(buf.data(), n);  // host -> little-endian (its own inverse)
            out.write(reinterpret_cast<const char*>(buf.data()),
                      static_cast<std::streamsize>(buf.size()));
        }
        marker(bytes);
    }
}

void writeAscii(std::ostream& out, const std::vector<StructuredGrid>& blocks) {
    std::string line;
    char num[40];
    auto put = [&](double v) {
        const auto r = std::to_chars(num, num + sizeof num, v, std::chars_format::general, 17);
        if (!line.empty()) line += ' ';
        line.append(num, r.ptr);
    };
    auto flush = [&] {
        line += '\n';
        out.write(line.data(), static_cast<std::streamsize>(line.size()));
        line.clear();
    };
    out << blocks.size() << '\n';
    for (const StructuredGrid& g : blocks) {
        out << g.dims[0] << ' ' << g.dims[1] << ' ' << g.dims[2] << '\n';
    }
    for (const StructuredGrid& g : blocks) {
        const long n = g.nodeCount();
        for (int c = 0; c < 3; ++c) {
            for (long a = 0; a < n; ++a) {
                put(g.xyz[3 * a + c]);
                if (a % 4 == 3) flush();
            }
            if (!line.empty()) flush();
        }
    }
}

// ---- binary reading --------------------------------------------------------------------

class RecordReader {
  public:
    RecordReader(std::ifstream& in, const std::string& path, std::uint64_t size)
        : in_(in), path_(path), size_(size) {}

    std::uint64_t offset() const { return pos_; }
    std::uint64_t remaining() const { return size_ - pos_; }

    // Reads a leading marker; `what` names the record in messages.
    std::uint32_t begin(const std::string& what) {
        if (remaining() < 4) {
            fail(path_, "truncated: " + what + " record expected at byte " + std::to_string(pos_) +
                            ", but the file ends there");
        }
        unsigned char m[4];
        bytes(m, 4);
        return readLe32(m);
    }

    // Checks that `length` payload bytes plus the trailing marker are present.
    void requirePayload(std::uint32_t length, const std::string& what) {
        if (remaining() < static_cast<std::uint64_t>(length) + 4) {
            fail(path_, "truncated: " + what + " record of " + std::to_string(length) +
                            " bytes starts at byte " + std::to_string(pos_) + ", but only " +
                            std::to_string(remaining()) + " bytes remain (expected " +
                            std::to_string(length + 4ull) + " including the end marker)");
        }
    }

    void bytes(void* dst, std::uint64_t n) {
        in_.read(static_cast<char*>(dst), static_cast<std::streamsize>(n));
        if (static_cast<std::uint64_t>(in_.gcount()) != n) {
            fail(path_, "read error at byte " + std::to_string(pos_));
        }
        pos_ += n;
    }

    void skip(std::uint64_t n) {
        in_.seekg(static_cast<std::streamoff>(n), std::ios::cur);
        if (!in_) fail(path_, "read error at byte " + std::to_string(pos_));
        pos_ += n;
    }

    // Reads the trailing marker and checks it against the leading one.
    void end(std::uint32_t length, const std::string& what) {
        const std::uint64_t at = pos_;
        unsigned char m[4];
        bytes(m, 4);
        const std::uint32_t trailing = readLe32(m);
        if (trailing != length) {
            fail(path_, "mismatched record markers for " + what + ": leading " +
                            std::to_string(length) + ", trailing " + std::to_string(trailing) +
                            " (at byte " + std::to_string(at) + ")");
        }
    }

  private:
    std::ifstream& in_;
    const std::string& path_;
    std::uint64_t size_;
    std::uint64_t pos_ = 0;
};

std::vector<StructuredGrid> readBinary(std::ifstream& in, const std::string& path,
                                       std::uint64_t size) {
    RecordReader r(in, path, size);
    std::uint32_t len = r.begin("block count");
    r.requirePayload(len, "block count");
    unsigned char word[4];
    r.bytes(word, 4);
    const auto nb = static_cast<std::int32_t>(readLe32(word));
    r.end(len, "the block count");
    if (nb < 1) fail(path, "bad block count " + std::to_string(nb) + " (must be at least 1)");

    const std::uint64_t dimsBytes = 12 * static_cast<std::uint64_t>(nb);
    len = r.begin("dimensions");
    if (len != dimsBytes) {
        const bool twoD = len == 8 * static_cast<std::uint64_t>(nb);
        fail(path, "dimensions record has " + std::to_string(len) + " bytes, expected 12 * " +
                       std::to_string(nb) + " = " + std::to_string(dimsBytes) + " for " +
                       std::to_string(nb) + " blocks" +
                       (twoD ? " (this looks like a 2D file, which is not supported)" : ""));
    }
    r.requirePayload(len, "dimensions");
    std::vector<StructuredGrid> blocks(nb);
    for (int b = 0; b < nb; ++b) {
        StructuredGrid& g = blocks[b];
        g.name = "block" + std::to_string(b);
        for (int d = 0; d < 3; ++d) {
            r.bytes(word, 4);
            g.dims[d] = static_cast<std::int32_t>(readLe32(word));
        }
        if (g.dims[0] < 1 || g.dims[1] < 1 || g.dims[2] < 1) {
            fail(path, blockName(b) + ": bad dims " + std::to_string(g.dims[0]) + " x " +
                           std::to_string(g.dims[1]) + " x " + std::to_string(g.dims[2]) +
                           " (each must be at least 1)");
        }
        checkBlockSize(path, blockName(b), g.dims[0], g.dims[1], g.dims[2]);
    }
    r.end(len, "the dimensions");

    std::vector<double> coords;
    std::vector<float> coords32;
    for (int b = 0; b < nb; ++b) {
        StructuredGrid& g = blocks[b];
        const std::uint64_t n = static_cast<std::uint64_t>(g.dims[0]) *
                                static_cast<std::uint64_t>(g.dims[1]) *
                                static_cast<std::uint64_t>(g.dims[2]);
        const std::string what = blockName(b) + " coordinate";
        len = r.begin(what);
        // Accepted payloads: 3 float64 or float32 per node, optionally followed by int32 iblank.
        int realBytes = 0;
        bool iblank = false;
        if (len == 24 * n) {
            realBytes = 8;
        } else if (len == 12 * n) {
            realBytes = 4;
        } else if (len == 28 * n) {
            realBytes = 8;
            iblank = true;
        } else if (len == 16 * n) {
            realBytes = 4;
            iblank = true;
        } else {
            fail(path, blockName(b) + " (" + std::to_string(g.dims[0]) + " x " +
                           std::to_string(g.dims[1]) + " x " + std::to_string(g.dims[2]) +
                           " nodes): coordinate record has " + std::to_string(len) +
                           " bytes at byte " + std::to_string(r.offset() - 4) + ", expected 24 * " +
                           std::to_string(n) + " = " + std::to_string(24 * n) +
                           " (float64 x, y, z)");
        }
        r.requirePayload(len, what);
        g.xyz.resize(3 * n);
        if (realBytes == 8) {
            coords.resize(3 * n);
            r.bytes(coords.data(), 24 * n);
            fromLittleEndian<8>(coords.data(), 3 * n);
            for (int c = 0; c < 3; ++c) {
                for (std::uint64_t a = 0; a < n; ++a) g.xyz[3 * a + c] = coords[c * n + a];
            }
        } else {
            coords32.resize(3 * n);
            r.bytes(coords32.data(), 12 * n);
            fromLittleEndian<4>(coords32.data(), 3 * n);
            for (int c = 0; c < 3; ++c) {
                for (std::uint64_t a = 0; a < n; ++a) g.xyz[3 * a + c] = coords32[c * n + a];
            }
        }
        if (iblank) r.skip(4 * n);
        r.end(len, blockName(b));
        for (std::uint64_t a = 0; a < 3 * n; ++a) {
            if (!std::isfinite(g.xyz[a])) {
                fail(path, blockName(b) + ": " + kCoordName[a % 3] + " of node " +
                               std::to_string(a / 3) + " is not finite");
            }
        }
    }
    if (r.remaining() != 0) {
        fail(path, std::to_string(r.remaining()) +
                       " bytes of trailing data after the last block (at byte " +
                       std::to_string(r.offset()) + ")");
    }
    return blocks;
}

// ---- formatted reading ----------------------------------------------------------------

class Tokenizer {
  public:
    Tokenizer(const std::string& text, const std::string& path) : text_(text), path_(path) {}

    // The next token, or an empty view at the end of the text.
    std::string_view next() {
        while (pos_ < text_.size() && isSeparator(text_[pos_])) ++pos_;
        start_ = pos_;
        while (pos_ < text_.size() && !isSeparator(text_[pos_])) ++pos_;
        return std::string_view(text_).substr(start_, pos_ - start_);
    }

    // 1-based line of the last token.
    long line() const {
        long n = 1;
        for (std::size_t a = 0; a < start_ && a < text_.size(); ++a) n += text_[a] == '\n';
        return n;
    }

    long integer(const std::string& what) {
        const std::string_view t = next();
        if (t.empty()) {
            fail(path_, "truncated: " + what + " missing (file ends at line " +
                            std::to_string(line()) + ")");
        }
        long long v = 0;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        if (r.ec != std::errc() || r.ptr != t.data() + t.size() ||
            v > std::numeric_limits<int>::max() || v < std::numeric_limits<int>::min()) {
            fail(path_, what + " at line " + std::to_string(line()) + ": '" + std::string(t) +
                            "' is not an integer");
        }
        return static_cast<long>(v);
    }

    // Parses a real token; false if it is not a number (accepts a leading '+' and Fortran 'D').
    static bool real(std::string_view t, double& v) {
        char buf[64];
        if (!t.empty() && t[0] == '+') t.remove_prefix(1);
        if (t.empty() || t.size() >= sizeof buf) return false;
        for (std::size_t a = 0; a < t.size(); ++a) {
            buf[a] = (t[a] == 'D' || t[a] == 'd') ? 'e' : t[a];
        }
        const auto r = std::from_chars(buf, buf + t.size(), v);
        return r.ec == std::errc() && r.ptr == buf + t.size();
    }

  private:
    static bool isSeparator(char c) {
        return c == ' ' || c == '\n' || c == '\r' || c == '\t' || c == ',' || c == '\f' ||
               c == '\v';
    }
    const std::string& text_;
    const std::string& path_;
    std::size_t pos_ = 0, start_ = 0;
};

std::vector<StructuredGrid> readAscii(const std::string& text, const std::string& path) {
    Tokenizer tok(text, path);
    const long nb = tok.integer("block count");
    if (nb < 1) fail(path, "bad block count " + std::to_string(nb) + " (must be at least 1)");
    // Every block needs at least 3 tokens of dims: reject absurd counts before allocating.
    if (static_cast<std::uint64_t>(nb) > text.size() / 2) {
        fail(path, "block count " + std::to_string(nb) + " is impossible for a file of " +
                       std::to_string(text.size()) + " bytes");
    }
    std::vector<StructuredGrid> blocks(nb);
    std::uint64_t totalValues = 0;
    long tooBig = -1;  // first block whose dims need more values than the file can hold
    for (long b = 0; b < nb; ++b) {
        StructuredGrid& g = blocks[b];
        g.name = "block" + std::to_string(b);
        for (int d = 0; d < 3; ++d) {
            const long v =
                tok.integer(blockName(static_cast<int>(b)) + " dimension " + std::to_string(d));
            if (v < 1 || v > kMaxBlockNodes) {
                fail(path, blockName(static_cast<int>(b)) + ": bad dimension " + std::to_string(d) +
                               " = " + std::to_string(v) + " at line " +
                               std::to_string(tok.line()) + " (must lie in [1, 10^9])");
            }
            g.dims[d] = static_cast<int>(v);
        }
        checkBlockSize(path, blockName(static_cast<int>(b)), g.dims[0], g.dims[1], g.dims[2]);
        totalValues += 3 * static_cast<std::uint64_t>(g.dims[0]) *
                       static_cast<std::uint64_t>(g.dims[1]) *
                       static_cast<std::uint64_t>(g.dims[2]);
        // Each value takes at least two bytes (a digit and a separator).
        if (tooBig < 0 && totalValues > text.size() / 2 + 1) tooBig = b;
    }
    if (tooBig >= 0) {
        // Checked before allocating, so that bogus dims cannot exhaust memory.
        const StructuredGrid& g = blocks[tooBig];
        std::uint64_t upTo = 0;
        for (long b = 0; b <= tooBig; ++b) {
            upTo += 3 * static_cast<std::uint64_t>(blocks[b].nodeCount());
        }
        fail(path, "truncated or bad dims: the dims up to " + blockName(static_cast<int>(tooBig)) +
                       " (" + std::to_string(g.dims[0]) + " x " + std::to_string(g.dims[1]) +
                       " x " + std::to_string(g.dims[2]) + ") need " + std::to_string(upTo) +
                       " coordinates, more than a file of " + std::to_string(text.size()) +
                       " bytes can hold");
    }
    for (long b = 0; b < nb; ++b) {
        StructuredGrid& g = blocks[b];
        const long n = g.nodeCount();
        g.xyz.resize(3 * static_cast<std::size_t>(n));
        for (int c = 0; c < 3; ++c) {
            for (long a = 0; a < n; ++a) {
                const std::string_view t = tok.next();
                auto where = [&] {
                    return blockName(static_cast<int>(b)) + ", " + kCoordName[c] + " coordinate " +
                           std::to_string(a);
                };
                if (t.empty()) {
                    fail(path, "truncated: " + blockName(static_cast<int>(b)) + " expected 3 * " +
                                   std::to_string(n) + " = " + std::to_string(3 * n) +
                                   " coordinates, found " + std::to_string(c * n + a) +
                                   " (file ends at line " + std::to_string(tok.line()) + ")");
                }
                double v = 0;
                if (!Tokenizer::real(t, v)) {
                    fail(path, where() + " at line " + std::to_string(tok.line()) + ": '" +
                                   std::string(t) + "' is not a number");
                }
                if (!std::isfinite(v)) {
                    fail(path, where() + " at line " + std::to_string(tok.line()) + ": '" +
                                   std::string(t) + "' is not finite");
                }
                g.xyz[3 * a + c] = v;
            }
        }
    }
    const std::string_view extra = tok.next();
    if (!extra.empty()) {
        fail(path, "unexpected data after the last block at line " + std::to_string(tok.line()) +
                       ": '" + std::string(extra.substr(0, 32)) + "'");
    }
    return blocks;
}

}  // namespace

void writePlot3d(const std::string& path, const std::vector<StructuredGrid>& blocks, bool binary) {
    if (blocks.empty()) throw GeometryError("Plot3D output '" + path + "': no blocks to write");
    for (int b = 0; b < static_cast<int>(blocks.size()); ++b) checkBlockForWriting(blocks, b);
    // Write to a temporary file and rename: an existing file is never left half-written.
    const std::string tmp = path + ".tmp";
    auto cannot = [&](const std::string& what) {
        const int err = errno;
        std::remove(tmp.c_str());
        fail(path, "cannot " + what + (err ? std::string(": ") + std::strerror(err) : ""));
    };
    {
        errno = 0;
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) cannot("write");
        out.imbue(std::locale::classic());  // no digit grouping from a global locale
        try {
            if (binary) {
                writeBinary(out, path, blocks);
            } else {
                writeAscii(out, blocks);
            }
        } catch (...) {
            out.close();
            std::remove(tmp.c_str());
            throw;
        }
        out.close();
        if (!out) cannot("write");
    }
    errno = 0;
    if (std::rename(tmp.c_str(), path.c_str()) != 0) cannot("replace");
}

std::vector<StructuredGrid> readPlot3d(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        throw InputError("cannot open Plot3D file '" + path + "': it is a directory");
    }
    errno = 0;
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) {
        throw InputError("cannot open Plot3D file '" + path + "'" +
                         (errno ? std::string(": ") + std::strerror(errno) : ""));
    }
    const std::streamoff end = in.tellg();
    if (end < 0) fail(path, "cannot determine the file size");
    const auto size = static_cast<std::uint64_t>(end);
    if (size == 0) fail(path, "the file is empty");
    in.seekg(0);
    unsigned char head[64] = {};
    const std::size_t nHead = static_cast<std::size_t>(std::min<std::uint64_t>(size, sizeof head));
    in.read(reinterpret_cast<char*>(head), static_cast<std::streamsize>(nHead));
    in.seekg(0);
    if (nHead >= 4) {
        const std::uint32_t le = readLe32(head);
        const std::uint32_t be =
            (le >> 24) | ((le >> 8) & 0xff00u) | ((le << 8) & 0xff0000u) | (le << 24);
        if (le == 4) return readBinary(in, path, size);
        if (be == 4) fail(path, "big-endian unformatted file (only little-endian is supported)");
        if (le == 12) {
            fail(path,
                 "first record has 12 bytes: a single-block file without a block count, which is "
                 "not "
                 "supported (expected the multi-block layout, whose first record is the 4-byte "
                 "block count)");
        }
        bool text = true;
        for (std::size_t a = 0; a < nHead; ++a) {
            const unsigned char c = head[a];
            text = text &&
                   (c >= 0x20 || c == '\n' || c == '\r' || c == '\t' || c == '\f' || c == '\v') &&
                   c != 0x7f;
        }
        if (!text) {
            fail(path,
                 "neither formatted text nor a multi-block unformatted file: the first record "
                 "marker is " +
                     std::to_string(le) + ", expected 4");
        }
    }
    std::string text(static_cast<std::size_t>(size), '\0');
    in.read(text.data(), static_cast<std::streamsize>(size));
    if (static_cast<std::uint64_t>(in.gcount()) != size) fail(path, "read error");
    return readAscii(text, path);
}

}  // namespace aero::mesh
