#include "cli/CliSupport.h"

#include <cctype>
#include <csignal>
#include <fstream>
#include <sstream>

#include "cad/Iges.h"
#include "io/PatchSetJson.h"
#include "study/GeometryFiles.h"

namespace aero::app {

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::atomic<bool> gCancelFlag{false};
extern "C" void onCancelSignal(int) { gCancelFlag.store(true); }

}  // namespace

CancelOnSignal::CancelOnSignal() {
    gCancelFlag.store(false);
    oldInt_ = std::signal(SIGINT, onCancelSignal);
    oldTerm_ = std::signal(SIGTERM, onCancelSignal);
}

CancelOnSignal::~CancelOnSignal() {
    std::signal(SIGINT, oldInt_);
    std::signal(SIGTERM, oldTerm_);
}

std::atomic<bool>* CancelOnSignal::flag() { return &gCancelFlag; }

bool hasFlag(const Args& a, const char* flag) {
    for (const auto& s : a) {
        if (s == flag) return true;
    }
    return false;
}

std::string extension(const std::string& path) {
    const auto dot = path.find_last_of('.');
    const auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    return lower(path.substr(dot + 1));
}

geometry::PatchSet loadPatchSet(const std::string& path) {
    cad::ReadReport report;
    geometry::PatchSet set = study::loadGeometry(path, &report);
    for (const std::string& w : report.warnings) std::cerr << "aeroform-cli: warning: '" << path << "': " << w << "\n";
    return set;
}

void savePatchSet(const geometry::PatchSet& set, const std::string& path) { study::saveGeometry(set, path); }

int usageError(const char* command, const std::string& why, const char* help) {
    std::cerr << "aeroform-cli " << command << ": " << why << "\n\n" << help;
    return kUsage;
}

std::vector<std::string> splitList(const std::string& list) {
    std::vector<std::string> out;
    std::stringstream in(list);
    std::string item;
    while (std::getline(in, item, ',')) {
        if (!item.empty()) out.push_back(item);
    }
    return out;
}

bool parse(const Args& args, const std::set<std::string>& flags, const std::set<std::string>& valued,
           std::vector<std::string>& positional, std::map<std::string, std::string>& values, std::string& error) {
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (valued.count(a)) {
            if (i + 1 >= args.size()) {
                error = "option " + a + " needs a value";
                return false;
            }
            values[a] = args[++i];
        } else if (flags.count(a)) {
            values[a] = "1";
        } else if (a.size() > 1 && a[0] == '-') {
            error = "unknown option '" + a + "'";
            return false;
        } else {
            positional.push_back(a);
        }
    }
    return true;
}

nlohmann::ordered_json wallBendJson(const mesh::WallBend& b) {
    return {{"degrees", b.degrees}, {"block", b.block}, {"block_name", b.blockName},
            {"node", b.node},       {"neighbour", b.neighbour}, {"x", b.x}};
}

}  // namespace aero::app
