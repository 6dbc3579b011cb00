#include "flow/FlowMesh.h"

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

#include "common/Error.h"

namespace aero::flow {

bool onFace(const std::array<int, 3>& dims, long n, int f) {
    const std::array<int, 3> idx = nodeIndex(dims, n);
    const int d = faceDirection(f);
    return idx[d] == (faceIsMax(f) ? dims[d] - 1 : 0);
}

std::vector<long> faceNodes(const std::array<int, 3>& dims, int f) {
    const int d = faceDirection(f), a = d == 0 ? 1 : 0, b = d == 2 ? 1 : 2;
    const int fixed = faceIsMax(f) ? dims[d] - 1 : 0;
    std::vector<long> out;
    out.reserve(static_cast<std::size_t>(dims[a]) * dims[b]);
    for (int ib = 0; ib < dims[b]; ++ib) {
        for (int ia = 0; ia < dims[a]; ++ia) {
            int idx[3];
            idx[d] = fixed;
            idx[a] = ia;
            idx[b] = ib;
            out.push_back(idx[0] + static_cast<long>(dims[0]) * (idx[1] + static_cast<long>(dims[1]) * idx[2]));
        }
    }
    return out;
}

long faceNodeIndex(const std::array<int, 3>& dims, int f, long n) {
    const int d = faceDirection(f), a = d == 0 ? 1 : 0, b = d == 2 ? 1 : 2;
    const std::array<int, 3> idx = nodeIndex(dims, n);
    return idx[a] + static_cast<long>(dims[a]) * idx[b];
}

namespace {
std::string faceLabel(const FlowBlock& b, int index, int f) {
    return "block " + std::to_string(index + 1) + " ('" + b.name + "') face " + std::to_string(f);
}

// Groups the wall nodes that interface pairs join (union-find over global nodes) into junctions.
void findWallJunctions(FlowMesh& fm) {
    std::unordered_map<long, long> parent;
    auto find = [&](long n) {
        long r = n;
        while (parent[r] != r) r = parent[r];
        while (parent[n] != r) n = std::exchange(parent[n], r);
        return r;
    };
    for (const InterfacePatch& ip : fm.interfaces) {
        const long offA = fm.blocks[ip.blockA].offset, offB = fm.blocks[ip.blockB].offset;
        for (const auto& pr : ip.nodes) {
            const long a = offA + pr[0], b = offB + pr[1];
            parent.try_emplace(a, a);
            parent.try_emplace(b, b);
            parent[find(a)] = find(b);
        }
    }
    struct Member {
        int block, face;
        long index;  // in faceNodes order
        long node;   // global
    };
    std::map<long, std::vector<Member>> groups;  // by root: deterministic order
    for (int b = 0; b < static_cast<int>(fm.blocks.size()); ++b) {
        const FlowBlock& blk = fm.blocks[b];
        for (int f = 0; f < 6; ++f) {
            if (blk.faces[f].kind != mesh::BoundaryKind::Wall) continue;
            const std::vector<long> nodes = faceNodes(blk.dims, f);
            for (long a = 0; a < static_cast<long>(nodes.size()); ++a) {
                const long g = blk.offset + nodes[a];
                if (parent.count(g)) groups[find(g)].push_back({b, f, a, g});
            }
        }
    }
    for (const auto& [root, members] : groups) {
        if (members.size() < 2) continue;
        const int id = static_cast<int>(fm.wallJunctions.size());
        WallJunction& j = fm.wallJunctions.emplace_back();
        for (const Member& m : members) {
            FlowBlock& blk = fm.blocks[m.block];
            std::vector<int>& slot = blk.junction[m.face];
            if (slot.empty()) slot.assign(faceNodes(blk.dims, m.face).size(), -1);
            slot[m.index] = id;
            j.members.push_back({m.node, m.face});
        }
    }
}

}  // namespace

FlowMesh makeFlowMesh(std::vector<FlowBlock> blocks, const std::vector<mesh::NodePair>& pairs) {
    FlowMesh fm;
    fm.blocks = std::move(blocks);
    long offset = 0;
    for (std::size_t b = 0; b < fm.blocks.size(); ++b) {
        FlowBlock& blk = fm.blocks[b];
        for (int d = 0; d < 3; ++d) {
            if (blk.dims[d] < 2) {
                throw GeometryError("flow: " + faceLabel(blk, static_cast<int>(b), 2 * d) +
                                    ": a block needs at least 2 nodes in every direction");
            }
        }
        blk.offset = offset;
        offset += blk.nodeCount();
    }
    fm.nodeCount = offset;

    const int nb = static_cast<int>(fm.blocks.size());
    std::map<std::pair<int, int>, int> patchOf;  // (block, face) of side A -> patch index
    for (const mesh::NodePair& p : pairs) {
        if (p.blockA < 0 || p.blockA >= nb || p.blockB < 0 || p.blockB >= nb) {
            throw GeometryError("flow: an interface node pair names a block that does not exist");
        }
        int found = 0;
        int fa = -1, fb = -1;
        const FlowBlock& A = fm.blocks[p.blockA];
        const FlowBlock& B = fm.blocks[p.blockB];
        for (int f = 0; f < 6; ++f) {
            const mesh::FaceBoundary& face = A.faces[f];
            if (face.kind != mesh::BoundaryKind::Interface || face.neighbour != p.blockB) continue;
            if (face.neighbourFace < 0 || face.neighbourFace > 5) continue;
            if (p.blockA == p.blockB && face.neighbourFace == f) continue;
            if (!onFace(A.dims, p.nodeA, f) || !onFace(B.dims, p.nodeB, face.neighbourFace)) continue;
            ++found;
            fa = f;
            fb = face.neighbourFace;
        }
        if (found != 1) {
            throw GeometryError("flow: interface node " + std::to_string(p.nodeA) + " of " +
                                faceLabel(A, p.blockA, fa < 0 ? 0 : fa) + " against block " +
                                std::to_string(p.blockB + 1) + " ('" + B.name + "') " +
                                (found == 0 ? "lies on no interface face joining the two blocks"
                                            : "lies on several interface faces joining them"));
        }
        // A face pair is stored once, with the side seen first as A.
        auto it = patchOf.find({p.blockB, fb});
        if (it != patchOf.end() && fm.interfaces[it->second].blockA == p.blockB &&
            fm.interfaces[it->second].faceA == fb) {
            fm.interfaces[it->second].nodes.push_back({p.nodeB, p.nodeA});
            continue;
        }
        auto [jt, inserted] = patchOf.try_emplace({p.blockA, fa}, static_cast<int>(fm.interfaces.size()));
        if (inserted) fm.interfaces.push_back({p.blockA, fa, p.blockB, fb, {}});
        fm.interfaces[jt->second].nodes.push_back({p.nodeA, p.nodeB});
    }

    // Every interface face must be paired node for node: each of its nodes in exactly one pair
    // (a count of pairs alone would take a repeated pair for a missing one).
    std::map<std::pair<int, int>, std::set<long>> pairedNodes;
    std::map<std::pair<int, int>, long> pairCount;
    for (const InterfacePatch& ip : fm.interfaces) {
        for (const auto& pr : ip.nodes) {
            pairedNodes[{ip.blockA, ip.faceA}].insert(pr[0]);
            pairedNodes[{ip.blockB, ip.faceB}].insert(pr[1]);
        }
        pairCount[{ip.blockA, ip.faceA}] += static_cast<long>(ip.nodes.size());
        pairCount[{ip.blockB, ip.faceB}] += static_cast<long>(ip.nodes.size());
    }
    for (int b = 0; b < nb; ++b) {
        const FlowBlock& blk = fm.blocks[b];
        for (int f = 0; f < 6; ++f) {
            if (blk.faces[f].kind != mesh::BoundaryKind::Interface) continue;
            const long expected = static_cast<long>(faceNodes(blk.dims, f).size());
            const long got = pairedNodes.count({b, f}) ? static_cast<long>(pairedNodes[{b, f}].size()) : 0;
            const long pairTotal = pairCount.count({b, f}) ? pairCount[{b, f}] : 0;
            if (got != expected || pairTotal != got) {
                throw GeometryError("flow: " + faceLabel(blk, b, f) + " is an interface but " +
                                    std::to_string(got) + " of its " + std::to_string(expected) +
                                    " nodes have an interface partner" +
                                    (pairTotal != got ? " (" + std::to_string(pairTotal) +
                                                        " pairs: a node is paired more than once)"
                                                  : std::string()));
            }
        }
    }
    findWallJunctions(fm);
    return fm;
}

FlowMesh makeFlowMesh(const mesh::MultiBlockMesh& m, const std::vector<mesh::StructuredGrid>& grids) {
    if (grids.size() != m.blocks.size()) {
        throw GeometryError("flow: " + std::to_string(grids.size()) + " grids for " +
                            std::to_string(m.blocks.size()) + " mesh blocks");
    }
    std::vector<FlowBlock> blocks(m.blocks.size());
    for (std::size_t b = 0; b < m.blocks.size(); ++b) {
        blocks[b].name = m.blocks[b].name;
        blocks[b].dims = grids[b].dims;
        blocks[b].faces = m.blocks[b].faces;
    }
    return makeFlowMesh(std::move(blocks), m.interfaceNodes);
}

std::vector<double> gatherCoordinates(const FlowMesh& fm,
                                      const std::vector<mesh::StructuredGrid>& grids) {
    std::vector<double> x(3 * static_cast<std::size_t>(fm.nodeCount));
    for (std::size_t b = 0; b < fm.blocks.size(); ++b) {
        const FlowBlock& blk = fm.blocks[b];
        if (grids.at(b).dims != blk.dims) {
            throw GeometryError("flow: grid of block " + std::to_string(b + 1) + " ('" + blk.name +
                                "') does not match the flow mesh layout");
        }
        std::copy(grids[b].xyz.begin(), grids[b].xyz.end(), x.begin() + 3 * blk.offset);
    }
    return x;
}

std::vector<int> blockGroups(const FlowMesh& fm, int groups) {
    std::vector<int> group(fm.nodeCount, 0);
    for (const FlowBlock& b : fm.blocks) {
        const double middle = static_cast<double>(b.offset) + 0.5 * static_cast<double>(b.nodeCount());
        const int g = static_cast<int>(groups * middle / static_cast<double>(fm.nodeCount));
        std::fill(group.begin() + b.offset, group.begin() + b.offset + b.nodeCount(), std::clamp(g, 0, groups - 1));
    }
    return group;
}

}  // namespace aero::flow
