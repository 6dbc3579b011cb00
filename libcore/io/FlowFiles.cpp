#include "io/FlowFiles.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/AtomicFile.h"
#include "common/Error.h"
#include "flow/Outputs.h"
#include "io/InputFile.h"
#include "io/VtkXml.h"

namespace aero::io {

namespace {

constexpr char kMagic[16] = {'A', 'E', 'R', 'O', 'F', 'O', 'R', 'M', '-', 'R', 'E', 'S', 'T', 'A', 'R', 'T'};
constexpr std::uint32_t kRestartVersion = 2;  // 2: the blocks' grid parameters and corners (optional)

// FNV-1a, 64 bit: detects truncation and bit rot, not tampering.
struct Checksum {
    std::uint64_t h = 1469598103934665603ull;
    void add(const void* data, std::size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < n; ++i) {
            h ^= p[i];
            h *= 1099511628211ull;
        }
    }
};

class Writer {
public:
    explicit Writer(std::ofstream& out) : out_(out) {}
    template <class T>
    void put(const T& v) { bytes(&v, sizeof v); }
    void bytes(const void* data, std::size_t n) {
        sum_.add(data, n);
        out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
    }
    std::uint64_t checksum() const { return sum_.h; }

private:
    std::ofstream& out_;
    Checksum sum_;
};

class Reader {
public:
    Reader(std::ifstream& in, const std::string& path) : in_(in), path_(path) {}
    template <class T>
    T get(const char* what) {
        T v{};
        bytes(&v, sizeof v, what);
        return v;
    }
    void bytes(void* data, std::size_t n, const char* what) {
        in_.read(static_cast<char*>(data), static_cast<std::streamsize>(n));
        if (static_cast<std::size_t>(in_.gcount()) != n) {
            throw InputError("restart file '" + path_ + "': truncated (ends inside the " + what + ")");
        }
        sum_.add(data, n);
    }
    std::uint64_t checksum() const { return sum_.h; }

private:
    std::ifstream& in_;
    const std::string& path_;
    Checksum sum_;
};

void ensureParent(const std::string& path) {
    const auto parent = std::filesystem::path(path).parent_path();
    if (parent.empty()) return;
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
    if (ec) throw InputError("cannot create the folder of '" + path + "': " + ec.message());
}

void replaceWith(const std::string& tmp, const std::string& path) {
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw InputError("cannot write '" + path + "': rename failed");
    }
}

}  // namespace

void writeRestart(const std::string& path, const flow::FlowMesh& fm, const std::vector<double>& q,
                  const RestartInfo& info) {
    if (q.size() != static_cast<std::size_t>(flow::kVars * fm.nodeCount)) {
        throw Error("restart '" + path + "': state has " + std::to_string(q.size()) + " values, the grid needs " +
                    std::to_string(flow::kVars * fm.nodeCount));
    }
    if (!info.samples.empty()) {
        bool fits = info.samples.size() == fm.blocks.size();
        for (std::size_t b = 0; fits && b < fm.blocks.size(); ++b) {
            for (int d = 0; d < 3; ++d) fits = fits && info.samples[b][d].size() == static_cast<std::size_t>(fm.blocks[b].dims[d]);
        }
        if (!fits || info.corners.size() != fm.blocks.size()) {
            throw Error("restart '" + path + "': the grid parameters or corners do not match the grid's blocks");
        }
    }
    ensureParent(path);
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError("cannot write restart file '" + path + "'");
        Writer w(out);
        w.bytes(kMagic, sizeof kMagic);
        w.put(kRestartVersion);
        w.put(static_cast<std::uint32_t>(fm.blocks.size()));
        for (const flow::FlowBlock& b : fm.blocks) {
            for (int d = 0; d < 3; ++d) w.put(static_cast<std::int32_t>(b.dims[d]));
        }
        w.put(static_cast<std::uint8_t>(info.samples.empty() ? 0 : 1));
        for (const auto& block : info.samples) {
            for (const auto& u : block) w.bytes(u.data(), u.size() * sizeof(double));
        }
        if (!info.samples.empty()) {
            for (const auto& c : info.corners) w.bytes(c.data(), sizeof c);
        }
        w.put(info.freeStream.mach);
        w.put(info.freeStream.alphaDeg);
        w.put(info.freeStream.gamma);
        w.put(static_cast<std::int32_t>(info.iterations));
        w.put(info.residual);
        w.put(info.initialResidual);
        w.put(info.cflBase);
        w.put(info.lumping);
        w.put(static_cast<std::uint64_t>(fm.nodeCount));
        w.bytes(q.data(), q.size() * sizeof(double));
        const std::uint64_t sum = w.checksum();
        out.write(reinterpret_cast<const char*>(&sum), sizeof sum);
        out.flush();
        if (!out) {
            out.close();
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            throw InputError("cannot write restart file '" + path + "' (disk full?)");
        }
    }
    replaceWith(tmp, path);
}

RestartContents readRestartContents(const std::string& path) {
    checkInputFile(path, "restart file", std::uintmax_t(1) << 40);
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    if (ec || !in) throw InputError("cannot open restart file '" + path + "'");
    Reader r(in, path);
    char magic[sizeof kMagic];
    r.bytes(magic, sizeof magic, "header");
    if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) {
        throw InputError("'" + path + "' is not an Aeroform restart file");
    }
    const auto version = r.get<std::uint32_t>("header");
    if (version != 1 && version != kRestartVersion) {
        throw InputError("restart file '" + path + "': version " + std::to_string(version) + ", this build reads 1 to " +
                         std::to_string(kRestartVersion));
    }
    // Every count below is checked against the file's size before anything is allocated for it.
    const auto blocks = r.get<std::uint32_t>("header");
    if (blocks == 0 || blocks > size / 12) {
        throw InputError("restart file '" + path + "': " + std::to_string(blocks) + " blocks (the file is corrupt)");
    }
    RestartContents c;
    c.dims.resize(blocks);
    std::uint64_t nodes = 0, parameters = 0;
    for (std::uint32_t b = 0; b < blocks; ++b) {
        for (int d = 0; d < 3; ++d) {
            c.dims[b][d] = r.get<std::int32_t>("block sizes");
            if (c.dims[b][d] < 1 || static_cast<std::uintmax_t>(c.dims[b][d]) > size) {
                throw InputError("restart file '" + path + "': block " + std::to_string(b) + " has " +
                                 std::to_string(c.dims[b][d]) + " nodes along a direction (the file is corrupt)");
            }
            parameters += static_cast<std::uint64_t>(c.dims[b][d]);
        }
        nodes += static_cast<std::uint64_t>(c.dims[b][0]) * static_cast<std::uint64_t>(c.dims[b][1]) *
                 static_cast<std::uint64_t>(c.dims[b][2]);
        if (nodes > size / (flow::kVars * sizeof(double))) {
            throw InputError("restart file '" + path + "': truncated or corrupt (its blocks have more nodes than its " +
                             std::to_string(size) + " bytes hold)");
        }
    }
    RestartInfo& ri = c.info;
    if (version >= 2 && r.get<std::uint8_t>("grid parameters") != 0) {
        if (parameters > size / sizeof(double)) {
            throw InputError("restart file '" + path + "': truncated (ends inside the grid parameters)");
        }
        ri.samples.resize(blocks);
        for (std::uint32_t b = 0; b < blocks; ++b) {
            for (int d = 0; d < 3; ++d) {
                std::vector<double>& u = ri.samples[b][d];
                u.resize(static_cast<std::size_t>(c.dims[b][d]));
                r.bytes(u.data(), u.size() * sizeof(double), "grid parameters");
                for (std::size_t i = 0; i < u.size(); ++i) {
                    if (!std::isfinite(u[i]) || (i > 0 && !(u[i] > u[i - 1]))) {
                        throw InputError("restart file '" + path + "': the grid parameters of block " + std::to_string(b) +
                                         " do not increase along direction " + std::to_string(d) + " (the file is corrupt)");
                    }
                }
            }
        }
        if (blocks > size / sizeof(std::array<double, 24>)) {
            throw InputError("restart file '" + path + "': truncated (ends inside the block corners)");
        }
        ri.corners.resize(blocks);
        for (auto& corner : ri.corners) r.bytes(corner.data(), sizeof corner, "block corners");
    }
    ri.freeStream.mach = r.get<double>("free stream");
    ri.freeStream.alphaDeg = r.get<double>("free stream");
    ri.freeStream.gamma = r.get<double>("free stream");
    ri.iterations = r.get<std::int32_t>("iteration data");
    ri.residual = r.get<double>("iteration data");
    ri.initialResidual = r.get<double>("iteration data");
    ri.cflBase = r.get<double>("iteration data");
    ri.lumping = r.get<double>("iteration data");
    const auto storedNodes = r.get<std::uint64_t>("node count");
    if (storedNodes != nodes) {
        throw InputError("restart file '" + path + "': " + std::to_string(storedNodes) + " nodes, its blocks have " +
                         std::to_string(nodes) + " (the file is corrupt)");
    }
    c.q.resize(static_cast<std::size_t>(flow::kVars * nodes));
    r.bytes(c.q.data(), c.q.size() * sizeof(double), "state");
    const std::uint64_t expected = r.checksum();
    std::uint64_t stored = 0;
    in.read(reinterpret_cast<char*>(&stored), sizeof stored);
    if (in.gcount() != sizeof stored) throw InputError("restart file '" + path + "': truncated (no checksum)");
    if (stored != expected) throw InputError("restart file '" + path + "': checksum mismatch (the file is corrupt)");
    if (in.peek() != std::char_traits<char>::eof()) {
        // Anything after the checksum is not ours: two files concatenated, or a damaged copy.
        throw InputError("restart file '" + path + "': data after the checksum (the file is corrupt or not one restart)");
    }
    for (std::size_t i = 0; i < c.q.size(); ++i) {
        if (!std::isfinite(c.q[i])) {
            throw InputError("restart file '" + path + "': non-finite value at node " + std::to_string(i / flow::kVars));
        }
    }
    return c;
}

std::vector<std::array<double, 24>> blockCorners(const flow::FlowMesh& fm, const std::vector<double>& x) {
    std::vector<std::array<double, 24>> corners(fm.blocks.size());
    for (std::size_t b = 0; b < fm.blocks.size(); ++b) {
        const flow::FlowBlock& blk = fm.blocks[b];
        for (int c = 0; c < 8; ++c) {
            const long i = (c & 1) ? blk.dims[0] - 1 : 0, j = (c & 2) ? blk.dims[1] - 1 : 0, k = (c & 4) ? blk.dims[2] - 1 : 0;
            const long n = blk.offset + i + blk.dims[0] * (j + static_cast<long>(blk.dims[1]) * k);
            for (int d = 0; d < 3; ++d) corners[b][3 * c + d] = x[3 * static_cast<std::size_t>(n) + d];
        }
    }
    return corners;
}

void checkRestartLayout(const std::string& path, const RestartContents& file, const flow::FlowMesh& fm) {
    if (file.dims.size() != fm.blocks.size()) {
        throw InputError("restart file '" + path + "' was written for a grid of " + std::to_string(file.dims.size()) +
                         " blocks, this grid has " + std::to_string(fm.blocks.size()));
    }
    for (std::size_t b = 0; b < fm.blocks.size(); ++b) {
        const auto& dims = file.dims[b];
        const auto& want = fm.blocks[b].dims;
        if (dims[0] != want[0] || dims[1] != want[1] || dims[2] != want[2]) {
            auto str = [](auto a) { return std::to_string(a[0]) + "x" + std::to_string(a[1]) + "x" + std::to_string(a[2]); };
            throw InputError("restart file '" + path + "': block " + std::to_string(b) + " ('" + fm.blocks[b].name +
                             "') has " + str(dims) + " nodes in the file, " + str(want) + " in this grid");
        }
    }
}

std::vector<double> readRestart(const std::string& path, const flow::FlowMesh& fm, RestartInfo* info) {
    RestartContents c = readRestartContents(path);
    checkRestartLayout(path, c, fm);
    if (info) *info = std::move(c.info);
    return std::move(c.q);
}

void writeResidualCsv(const std::string& path, const std::vector<flow::FlowIteration>& history, int first) {
    ensureParent(path);
    const std::string tmp = path + ".tmp";
    {
        std::FILE* f = std::fopen(tmp.c_str(), "w");
        if (!f) throw InputError("cannot write residual history '" + path + "'");
        std::fprintf(f, "iteration,residual,relative_residual,cfl,linear_iterations,linear_residual,step_scale,seconds\n");
        for (const flow::FlowIteration& it : history) {
            std::fprintf(f, "%d,%.10e,%.10e,%.6e,%d,%.6e,%.6g,%.4f\n", first + it.iteration, it.residual,
                         it.relativeResidual, it.cfl, it.linearIterations, it.linearResidual, it.stepScale, it.seconds);
        }
        const bool ok = std::fflush(f) == 0 && !std::ferror(f);
        std::fclose(f);
        if (!ok) throw InputError("cannot write residual history '" + path + "' (disk full?)");
    }
    replaceWith(tmp, path);
}

namespace {

// Block and (i, j, k) of a global node.
void locate(const flow::FlowMesh& fm, long node, int& block, int idx[3]) {
    for (std::size_t b = 0; b < fm.blocks.size(); ++b) {
        const flow::FlowBlock& blk = fm.blocks[b];
        const long n = static_cast<long>(blk.dims[0]) * blk.dims[1] * blk.dims[2];
        if (node >= blk.offset && node < blk.offset + n) {
            const long l = node - blk.offset;
            block = static_cast<int>(b);
            idx[0] = static_cast<int>(l % blk.dims[0]);
            idx[1] = static_cast<int>((l / blk.dims[0]) % blk.dims[1]);
            idx[2] = static_cast<int>(l / (static_cast<long>(blk.dims[0]) * blk.dims[1]));
            return;
        }
    }
    block = -1;
}

}  // namespace

void writeWallPressureCsv(const std::string& path, const flow::FlowMesh& fm, const std::vector<double>& x,
                          const std::vector<double>& q, const flow::FreeStream& fs) {
    std::string text = "block,i,j,k,x,y,z,p,cp\n";
    char line[256];
    for (const flow::WallNode& w : flow::wallNodes(fm)) {
        int block = 0, idx[3] = {0, 0, 0};
        locate(fm, w.node, block, idx);
        const double p = flow::pressure(&q[flow::kVars * w.node], fs.gamma);
        std::snprintf(line, sizeof line, "%d,%d,%d,%d,%.10g,%.10g,%.10g,%.17g,%.10g\n", block, idx[0], idx[1], idx[2],
                      x[3 * w.node], x[3 * w.node + 1], x[3 * w.node + 2], p, (p - fs.pressure()) / fs.dynamicPressure());
        text += line;
    }
    ensureParent(path);
    writeTextAtomically(path, text, "wall pressure file");
}

std::vector<double> readWallPressureCsv(const std::string& path, const flow::FlowMesh& fm) {
    std::ifstream in(path);
    if (!in) throw InputError("cannot read the wall pressure file '" + path + "'");
    std::string line;
    std::getline(in, line);  // header
    const std::vector<flow::WallNode> wall = flow::wallNodes(fm);
    std::vector<double> p;
    int row = 1;
    while (std::getline(in, line)) {
        ++row;
        if (line.empty()) continue;
        const std::string where = "'" + path + "' line " + std::to_string(row);
        int block = 0, i = 0, j = 0, k = 0;
        double xx = 0, yy = 0, zz = 0, value = 0;
        if (std::sscanf(line.c_str(), "%d,%d,%d,%d,%lf,%lf,%lf,%lf", &block, &i, &j, &k, &xx, &yy, &zz, &value) != 8 ||
            !std::isfinite(value) || value <= 0) {
            throw InputError(where + ": expected block,i,j,k,x,y,z,p with a positive pressure");
        }
        if (p.size() >= wall.size()) {
            throw InputError(where + ": more rows than the grid's " + std::to_string(wall.size()) + " wall nodes (another grid?)");
        }
        int b = 0, idx[3] = {0, 0, 0};
        locate(fm, wall[p.size()].node, b, idx);
        if (b != block || idx[0] != i || idx[1] != j || idx[2] != k) {
            throw InputError(where + ": node (" + std::to_string(block) + ": " + std::to_string(i) + ", " + std::to_string(j) + ", " +
                             std::to_string(k) + ") is not the grid's wall node of this row, (" + std::to_string(b) + ": " +
                             std::to_string(idx[0]) + ", " + std::to_string(idx[1]) + ", " + std::to_string(idx[2]) +
                             ") (a file written for another grid?)");
        }
        p.push_back(value);
    }
    if (p.size() != wall.size()) {
        throw InputError("'" + path + "': " + std::to_string(p.size()) + " wall pressures for the grid's " +
                         std::to_string(wall.size()) + " wall nodes (another grid?)");
    }
    return p;
}

void writeFlowVtm(const std::string& path, const flow::FlowMesh& fm, const std::vector<double>& x,
                  const std::vector<double>& q, const flow::FreeStream& fs) {
    const std::vector<double> cp = flow::pressureCoefficient(fm, q, fs);
    const std::vector<double> mach = flow::machNumber(fm, q, fs.gamma);
    const std::vector<double> s = flow::entropy(fm, q, fs);
    auto slice = [](const std::vector<double>& v, int width, long first, long count) {
        return std::vector<double>(v.begin() + width * first, v.begin() + width * (first + count));
    };

    std::vector<StructuredBlock> volume, wall;
    for (const flow::FlowBlock& b : fm.blocks) {
        const long n = b.nodeCount();
        StructuredBlock sb{b.name, b.dims, slice(x, 3, b.offset, n), {}, {}};
        std::vector<double> rho(n), vel(3 * n), p(n);
        for (long i = 0; i < n; ++i) {
            const double* qi = &q[flow::kVars * (b.offset + i)];
            rho[i] = qi[0];
            for (int c = 0; c < 3; ++c) vel[3 * i + c] = qi[1 + c] / qi[0];
            p[i] = flow::pressure(qi, fs.gamma);
        }
        sb.pointData = {{"density", 1, std::move(rho)},
                        {"velocity", 3, std::move(vel)},
                        {"pressure", 1, std::move(p)},
                        {"Cp", 1, slice(cp, 1, b.offset, n)},
                        {"Mach", 1, slice(mach, 1, b.offset, n)},
                        {"entropy", 1, slice(s, 1, b.offset, n)}};
        volume.push_back(std::move(sb));

        for (int f = 0; f < 6; ++f) {
            if (b.faces[f].kind != mesh::BoundaryKind::Wall) continue;
            const int d = flow::faceDirection(f), t1 = d == 0 ? 1 : 0, t2 = d == 2 ? 1 : 2;
            const std::vector<long> nodes = flow::faceNodes(b.dims, f);
            StructuredBlock w{b.name + " face " + std::to_string(f), {b.dims[t1], b.dims[t2], 1}, {}, {}, {}};
            std::vector<double> wcp, wm, ws;
            for (long local : nodes) {
                const long g = b.offset + local;
                for (int c = 0; c < 3; ++c) w.points.push_back(x[3 * g + c]);
                wcp.push_back(cp[g]);
                wm.push_back(mach[g]);
                ws.push_back(s[g]);
            }
            w.pointData = {{"Cp", 1, std::move(wcp)}, {"Mach", 1, std::move(wm)}, {"entropy", 1, std::move(ws)}};
            wall.push_back(std::move(w));
        }
    }
    ensureParent(path);
    std::vector<MultiBlockGroup> groups{{"flow", std::move(volume)}};
    if (!wall.empty()) groups.push_back({"wall", std::move(wall)});
    writeVtm(path, groups);
}

void writeWarmState(const std::string& path, const std::vector<double>& q) {
    std::string bytes(sizeof(std::uint64_t) + q.size() * sizeof(double), '\0');
    const std::uint64_t n = q.size();
    std::memcpy(bytes.data(), &n, sizeof n);
    if (!q.empty()) std::memcpy(bytes.data() + sizeof n, q.data(), q.size() * sizeof(double));
    writeTextAtomically(path, bytes, "flow state");
}

std::vector<double> readWarmState(const std::string& path) {
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec || size < sizeof(std::uint64_t) || (size - sizeof(std::uint64_t)) % sizeof(double) != 0) return {};
    std::ifstream in(path, std::ios::binary);
    std::uint64_t n = 0;
    if (!in.read(reinterpret_cast<char*>(&n), sizeof n) || n != (size - sizeof n) / sizeof(double)) return {};
    std::vector<double> q(n);
    if (!in.read(reinterpret_cast<char*>(q.data()), static_cast<std::streamsize>(n * sizeof(double)))) return {};
    return q;
}

}  // namespace aero::io
