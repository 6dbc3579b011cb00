#pragma once
// Shared pieces of the CLI subcommands: exit codes, argument parsing, loading and saving patch
// sets by extension, and the exception boundary.
#include <atomic>
#include <filesystem>
#include <iostream>
#include <new>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/Error.h"
#include "flow/TimeAccurate.h"
#include "geometry/PatchSet.h"
#include "mesh/Quality.h"

namespace aero::app {

constexpr int kOk = 0, kFailed = 1, kUsage = 2;

using Args = std::vector<std::string>;

bool hasFlag(const Args& a, const char* flag);
std::string extension(const std::string& path);

/// Reads a patch set from .json (native), .igs/.iges or .stp/.step; other extensions are sniffed.
/// The reader's warnings (changes to the geometry) go to stderr.
geometry::PatchSet loadPatchSet(const std::string& path);
/// Writes .json, .igs/.iges or .stp/.step by extension; InputError for anything else.
void savePatchSet(const geometry::PatchSet& set, const std::string& path);

/// The wall's sharpest node-to-node bend as the JSON summaries of mesh and flow report it.
nlohmann::ordered_json wallBendJson(const mesh::WallBend& b);

/// Splits args into positionals and options; `flags` take no value, `valued` take one.
/// Returns false with `error` set on an unknown option or a missing value.
bool parse(const Args& args, const std::set<std::string>& flags, const std::set<std::string>& valued,
           std::vector<std::string>& positional, std::map<std::string, std::string>& values, std::string& error);

int usageError(const char* command, const std::string& why, const char* help);

/// The non-empty items of a comma-separated list ("CL,CD," -> {"CL", "CD"}).
std::vector<std::string> splitList(const std::string& list);

/// While one is alive, SIGINT (Ctrl+C) and SIGTERM set a flag instead of ending the process: the
/// work checks it between iterations, stops and keeps its state. The flag is cleared on
/// construction; the handlers from before come back on destruction (also when an exception
/// leaves the scope).
class CancelOnSignal {
public:
    CancelOnSignal();
    ~CancelOnSignal();
    CancelOnSignal(const CancelOnSignal&) = delete;
    CancelOnSignal& operator=(const CancelOnSignal&) = delete;
    /// The flag (one for the process, valid outside the object's life too).
    static std::atomic<bool>* flag();
    bool cancelled() const { return flag()->load(); }

private:
    void (*oldInt_)(int);
    void (*oldTerm_)(int);
};

/// Runs fn, turning libcore's exceptions into a message on stderr and exit code 1.
template <class Fn>
int guarded(const char* command, Fn&& fn) {
    try {
        return fn();
    } catch (const Error& e) {
        std::cerr << "aeroform-cli " << command << ": error: " << e.what() << "\n";
        return kFailed;
    } catch (const std::bad_alloc&) {
        std::cerr << "aeroform-cli " << command
                  << ": error: out of memory (the case needs more memory than this machine has; a coarser "
                     "mesh.level or a lower mesh.refine needs less)\n";
        return kFailed;
    } catch (const std::filesystem::filesystem_error& e) {
        std::cerr << "aeroform-cli " << command << ": error: " << e.code().message() << ": '" << e.path1().string() << "'"
                  << (e.path2().empty() ? std::string() : " -> '" + e.path2().string() + "'") << "\n";
        return kFailed;
    } catch (const std::exception& e) {
        std::cerr << "aeroform-cli " << command << ": internal error: " << e.what() << "\n";
        return kFailed;
    }
}

/// Subcommands implemented in their own files.
int cmdDeform(const Args& args);
int cmdMesh(const Args& args);
int cmdFit(const Args& args);
int cmdFlow(const Args& args);
int cmdSweep(const Args& args);
int cmdGradient(const Args& args);
int cmdGradientCheck(const Args& args);
int cmdOptimize(const Args& args);
/// The optimize command's work (also `aeroform --batch CASE` for cases with an "optimization"
/// section: then resumed when its history exists).
int runOptimize(const std::string& casePath, bool resume, bool fresh, bool json, bool quiet);
/// The deform command's work for a case file (also `aeroform --batch CASE`).
int runDeform(const std::string& casePath, bool json, bool list);
/// The mesh command's work (also `aeroform --batch CASE` for cases with a "mesh" section).
int runMesh(const std::string& casePath, bool json);
/// The flow command's work (also `aeroform --batch CASE` for cases with a "flow" section).
int runFlow(const std::string& casePath, const std::string& restart, bool json,
            const std::vector<std::string>& adjoints = {});
/// The flow command with --time-accurate: the case's flow forward in physical time.
int runTimeAccurate(const std::string& casePath, const std::string& restart, const flow::TimeAccurateOptions& options,
                    const std::string& historyCsv, bool json);

}  // namespace aero::app
