#include "study/Optimization.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/AtomicFile.h"
#include "common/Error.h"
#include "common/FileLock.h"
#include "common/Format.h"
#include "ffd/ShapeConstraints.h"
#include "io/FlowFiles.h"
#include "io/GeometryVtk.h"
#include "io/VtkXml.h"
#include "mesh/Quality.h"
#include "study/GeometryFiles.h"
#include "study/Gradient.h"

namespace aero::study {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Kind = OptimizationRecord::Kind;

namespace {

constexpr double kCornerRatioRho = 50;  // the grid constraint's KS sharpness (io/Options.cpp documents it)
constexpr double kWallBendRho = 1000;   // the wall-bend constraint's (on 1 - cos of the bend)
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// The status of a converged flow refused by optimization.max_entropy or max_entropy_rise.
constexpr const char* kUnresolved = "flow-unresolved";
// Flow states kept on disk for warm starts besides the optimizer's last two iterates: the newest
// accepted evaluations (a line search's trials, and the design each came from).
constexpr std::size_t kKeptStates = 6;
constexpr double kNearlyFeasible = 1e-3;  // OptimizationSummary::nearlyFeasibleEvaluation

// The planform of an evaluated shape for the history (zeros when there is none: a design whose
// lattice folded before its shape was built, or trimmed patches).
geometry::Planform planformOf(const geometry::PatchSet& shape) {
    if (shape.patches.empty()) return {};
    try {
        return geometry::planform(shape);
    } catch (const GeometryError&) {
        return {};
    }
}

double since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// JSON numbers round-trip doubles exactly (shortest representation); NaN and infinities become
// null and come back as NaN.
Json number(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }
double number(const Json& j) { return j.is_number() ? j.get<double>() : kNaN; }
Json numbers(const std::vector<double>& v) {
    Json a = Json::array();
    for (double x : v) a.push_back(number(x));
    return a;
}
std::vector<double> numbers(const Json& j) {
    std::vector<double> v;
    for (const Json& x : j) v.push_back(number(x));
    return v;
}

Kind kindByName(const std::string& s, const std::string& where) {
    for (Kind k : {Kind::Header, Kind::Values, Kind::Gradient, Kind::Iteration}) {
        if (s == recordKindName(k)) return k;
    }
    throw InputError(where + ": unknown record kind '" + s + "'");
}

Json toJson(const OptimizationRecord& r) {
    Json j;
    j["kind"] = recordKindName(r.kind);
    switch (r.kind) {
        case Kind::Header:
            j["optimizer"] = r.optimizer;
            j["objective"] = r.objectiveName;
            j["variables"] = r.names;
            j["constraints"] = r.constraintNames;
            break;
        case Kind::Values:
            j["evaluation"] = r.index;
            j["x"] = numbers(r.x);
            j["ok"] = r.ok;
            j["status"] = r.status;
            if (!r.message.empty()) j["message"] = r.message;
            j["objective"] = number(r.objective);
            j["constraints"] = numbers(r.constraints);
            j["J"] = number(r.J);
            j["CL"] = number(r.CL);
            j["CD"] = number(r.CD);
            j["CM"] = number(r.CM);
            j["volume"] = number(r.volume);
            if (r.planform.projectedArea > 0) {
                j["half_span"] = number(r.planform.halfSpan);
                j["projected_area"] = number(r.planform.projectedArea);
                j["aspect_ratio"] = number(r.planform.aspectRatio);
            }
            j["corner_ratio"] = number(r.cornerRatio);
            j["wall_bend"] = number(r.wallBend);
            if (std::isfinite(r.growingMode)) j["growing_mode_rate"] = r.growingMode;
            j["max_mach"] = number(r.maxMach);
            j["max_entropy"] = number(r.maxEntropy);
            j["alpha"] = number(r.alphaDeg);
            j["flow_iterations"] = r.flowIterations;
            j["warm_from"] = r.warmFrom;
            j["seconds"] = number(r.seconds);
            break;
        case Kind::Gradient: {
            j["gradient"] = r.index;
            j["x"] = numbers(r.x);
            j["ok"] = r.ok;
            if (!r.message.empty()) j["message"] = r.message;
            j["d_objective"] = numbers(r.dObjective);
            Json dc = Json::array();
            for (const auto& row : r.dConstraints) dc.push_back(numbers(row));
            j["d_constraints"] = dc;
            j["adjoint_iterations"] = r.adjointIterations;
            j["seconds"] = number(r.seconds);
            break;
        }
        case Kind::Iteration:
            j["iteration"] = r.index;
            j["evaluations"] = r.evaluations;
            j["gradients"] = r.gradients;
            j["objective"] = number(r.objective);
            j["optimality"] = number(r.optimality);
            j["feasibility"] = number(r.feasibility);
            j["x"] = numbers(r.x);
            break;
    }
    return j;
}

OptimizationRecord fromJson(const Json& j, const std::string& where) {
    OptimizationRecord r;
    r.kind = kindByName(j.at("kind").get<std::string>(), where);
    switch (r.kind) {
        case Kind::Header:
            r.optimizer = j.at("optimizer").get<std::string>();
            r.objectiveName = j.at("objective").get<std::string>();
            r.names = j.at("variables").get<std::vector<std::string>>();
            if (j.contains("constraints")) r.constraintNames = j["constraints"].get<std::vector<std::string>>();
            break;
        case Kind::Values:
            r.index = j.at("evaluation").get<int>();
            r.x = numbers(j.at("x"));
            r.ok = j.at("ok").get<bool>();
            r.status = j.at("status").get<std::string>();
            if (j.contains("message")) r.message = j["message"].get<std::string>();
            r.objective = number(j.at("objective"));
            r.constraints = numbers(j.at("constraints"));
            r.J = number(j.at("J"));
            r.CL = number(j.at("CL"));
            r.CD = number(j.at("CD"));
            r.CM = number(j.at("CM"));
            r.volume = number(j.at("volume"));
            if (j.contains("projected_area")) {
                r.planform.halfSpan = number(j.at("half_span"));
                r.planform.projectedArea = number(j.at("projected_area"));
                r.planform.aspectRatio = number(j.at("aspect_ratio"));
            }
            if (j.contains("corner_ratio")) r.cornerRatio = number(j["corner_ratio"]);
            if (j.contains("wall_bend")) r.wallBend = number(j["wall_bend"]);
            if (j.contains("growing_mode_rate")) r.growingMode = number(j["growing_mode_rate"]);
            if (j.contains("max_mach")) r.maxMach = number(j["max_mach"]);
            if (j.contains("max_entropy")) r.maxEntropy = number(j["max_entropy"]);
            r.alphaDeg = number(j.at("alpha"));
            r.flowIterations = j.at("flow_iterations").get<int>();
            r.warmFrom = j.at("warm_from").get<int>();
            r.seconds = number(j.at("seconds"));
            break;
        case Kind::Gradient:
            r.index = j.at("gradient").get<int>();
            r.x = numbers(j.at("x"));
            r.ok = j.at("ok").get<bool>();
            if (j.contains("message")) r.message = j["message"].get<std::string>();
            r.dObjective = numbers(j.at("d_objective"));
            for (const Json& row : j.at("d_constraints")) r.dConstraints.push_back(numbers(row));
            r.adjointIterations = j.at("adjoint_iterations").get<int>();
            r.seconds = number(j.at("seconds"));
            break;
        case Kind::Iteration:
            r.index = j.at("iteration").get<int>();
            r.evaluations = j.at("evaluations").get<int>();
            r.gradients = j.at("gradients").get<int>();
            r.objective = number(j.at("objective"));
            r.optimality = number(j.at("optimality"));
            r.feasibility = number(j.at("feasibility"));
            r.x = numbers(j.at("x"));
            break;
    }
    return r;
}

// Appends one line and makes it durable before returning (a record is either whole on disk or,
// cut by a kill, an incomplete last line that readHistory drops).
void appendLine(const std::string& path, const std::string& line, const char* what) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) throw InputError(std::string("cannot write ") + what + " '" + path + "': " + std::strerror(errno));
    const std::string text = line + "\n";
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t w = ::write(fd, text.data() + done, text.size() - done);
        if (w < 0) {
            if (errno == EINTR) continue;
            const int e = errno;
            ::close(fd);
            throw InputError(std::string("cannot write ") + what + " '" + path + "': " + std::strerror(e));
        }
        done += static_cast<std::size_t>(w);
    }
    ::fsync(fd);
    ::close(fd);
}

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Flow states kept for warm starts: raw doubles behind a count.
std::string csvText(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char ch : s) {
        if (ch == '"') out += '"';
        out += ch == '\n' ? ' ' : ch;
    }
    return out + "\"";
}

std::string csvNumber(double v) { return std::isfinite(v) ? format("%.17g", v) : std::string(); }

// The two CSV views of the history, rebuilt from the records on resume and appended as they come.
class CsvHistory {
public:
    CsvHistory(std::string evaluations, std::string iterations, const std::vector<std::string>& names)
        : evaluations_(std::move(evaluations)), iterations_(std::move(iterations)), names_(names) {}

    void rewrite(const std::vector<OptimizationRecord>& records) {
        std::string e = evaluationHeader(), i = iterationHeader();
        for (const OptimizationRecord& r : records) {
            if (r.kind == Kind::Values || r.kind == Kind::Gradient) e += evaluationRow(r) + "\n";
            if (r.kind == Kind::Iteration) i += iterationRow(r) + "\n";
            if (r.kind == Kind::Values) values_[r.index] = r;
        }
        writeTextAtomically(evaluations_, e, "history file");
        writeTextAtomically(iterations_, i, "history file");
    }

    void append(const OptimizationRecord& r) {
        if (r.kind == Kind::Values) values_[r.index] = r;
        if (r.kind == Kind::Values || r.kind == Kind::Gradient) appendLine(evaluations_, evaluationRow(r), "history file");
        if (r.kind == Kind::Iteration) appendLine(iterations_, iterationRow(r), "history file");
    }

    /// The values records by evaluation number.
    const std::map<int, OptimizationRecord>& values() const { return values_; }

    /// The values record at x (the last evaluated there), or null.
    const OptimizationRecord* valuesAt(const std::vector<double>& x) const {
        for (auto it = values_.rbegin(); it != values_.rend(); ++it) {
            if (sameBits(it->second.x, x)) return &it->second;
        }
        return nullptr;
    }

private:
    std::string evaluationHeader() const {
        std::string h = "record,number,status,objective,J,CL,CD,CL/CD,CM,volume,half_span,projected_area,aspect_ratio,"
                        "smallest_corner_ratio,sharpest_wall_bend,max_mach,max_entropy,"
                        "alpha_deg,flow_iterations,adjoint_iterations,seconds,message";
        for (const std::string& n : names_) h += "," + n;
        return h + "\n";
    }
    static std::string iterationHeader() {
        return "iteration,evaluations,gradients,objective,optimality,feasibility,J,CL,CD,CL/CD,volume,half_span,"
               "projected_area,aspect_ratio\n";
    }
    std::string evaluationRow(const OptimizationRecord& r) const {
        std::string s = std::string(recordKindName(r.kind)) + "," + std::to_string(r.index) + ",";
        if (r.kind == Kind::Values) {
            // A refused converged flow (flow-unresolved) has forces to plot, but no objective.
            const bool flow = hasConvergedFlow(r);
            s += csvText(r.status) + "," + csvNumber(r.ok ? r.objective : kNaN) + "," + csvNumber(r.ok ? r.J : kNaN) + "," +
                 csvNumber(flow ? r.CL : kNaN) + "," + csvNumber(flow ? r.CD : kNaN) + "," +
                 csvNumber(flow ? r.CL / r.CD : kNaN) + "," + csvNumber(flow ? r.CM : kNaN) + "," + csvNumber(r.volume) + "," +
                 planformFields(r.planform) + "," +
                 csvNumber(r.cornerRatio != 0 ? std::exp(r.cornerRatio) : kNaN) + "," +
                 csvNumber(r.wallBend != 0 ? r.wallBend : kNaN) + "," + csvNumber(flow ? r.maxMach : kNaN) + "," +
                 csvNumber(flow ? r.maxEntropy : kNaN) + "," + csvNumber(r.alphaDeg) + "," +
                 std::to_string(r.flowIterations) + ",," + csvNumber(r.seconds) + "," +
                 csvText(r.message);
        } else {
            // status, then objective .. flow_iterations empty (16 fields), then adjoint_iterations.
            s += std::string(r.ok ? "ok" : "failed") + ",,,,,,,,,,,,,,,,," + std::to_string(r.adjointIterations) + "," +
                 csvNumber(r.seconds) + "," + csvText(r.message);
        }
        for (double u : r.x) s += "," + csvNumber(u);
        return s;
    }
    // half_span, projected_area, aspect_ratio (empty when not computed).
    static std::string planformFields(const geometry::Planform& f) {
        if (!(f.projectedArea > 0)) return ",,";
        return csvNumber(f.halfSpan) + "," + csvNumber(f.projectedArea) + "," + csvNumber(f.aspectRatio);
    }
    std::string iterationRow(const OptimizationRecord& r) const {
        std::string s = std::to_string(r.index) + "," + std::to_string(r.evaluations) + "," + std::to_string(r.gradients) + "," +
                        csvNumber(r.objective) + "," + csvNumber(r.optimality) + "," + csvNumber(r.feasibility);
        const OptimizationRecord* v = valuesAt(r.x);
        if (v && v->ok) {
            s += "," + csvNumber(v->J) + "," + csvNumber(v->CL) + "," + csvNumber(v->CD) + "," + csvNumber(v->CL / v->CD) + "," +
                 csvNumber(v->volume) + "," + planformFields(v->planform);
        } else {
            s += ",,,,,,,,";
        }
        return s;
    }

    std::string evaluations_, iterations_;
    std::vector<std::string> names_;
    std::map<int, OptimizationRecord> values_;
};

// The optimizer's variable i is design variable i divided by this (optimization.variable_scaling).
std::vector<double> variableScales(const io::OptimizationCase& oc, const std::vector<ffd::DesignVariable>& vars) {
    std::vector<double> scale(vars.size());
    for (std::size_t i = 0; i < vars.size(); ++i) {
        scale[i] = oc.rangeScaling && vars[i].upper > vars[i].lower ? vars[i].upper - vars[i].lower : 1.0;
    }
    return scale;
}

// ... and its alpha, the angle of attack divided by this (degrees per unit).
double alphaScale(const io::OptimizationCase& oc) { return oc.rangeScaling ? oc.alphaUpper - oc.alphaLower : 1.0; }

}  // namespace

StartDesign startDesign(const io::CaseFile& c, const ffd::FfdModel& model, const std::vector<double>& own) {
    const io::OptimizationCase& oc = c.optimization;
    StartDesign s{own, c.flow.freeStream.alphaDeg, 0};
    if (oc.startDesign.empty()) return s;
    const std::string key = "'" + c.path + "': optimization.start_design: ";
    try {
        const io::CaseFile from = io::readCase(oc.startDesign);
        s.values = io::designValues(from, model);
        if (oc.alphaVariable && from.flow.present) s.alphaDeg = from.flow.freeStream.alphaDeg;
    } catch (const Error& e) {
        throw CaseError(key + e.what());
    }
    if (oc.alphaVariable && !(s.alphaDeg >= oc.alphaLower && s.alphaDeg <= oc.alphaUpper)) {
        throw CaseError(key + format("'%s' has flow.alpha %.6g, outside [alpha_lower, alpha_upper] = [%.6g, %.6g]",
                                     oc.startDesign.c_str(), s.alphaDeg, oc.alphaLower, oc.alphaUpper));
    }
    for (std::size_t i = 0; i < own.size(); ++i) s.changed += s.values[i] != own[i] ? 1 : 0;
    return s;
}

bool hasConvergedFlow(const OptimizationRecord& r) {
    // A refused record written before the forces were kept has none (CD 0).
    return r.kind == Kind::Values && (r.ok || (r.status == kUnresolved && r.CD != 0));
}

int closestWarmStart(const std::vector<WarmCandidate>& candidates, const std::vector<double>& x) {
    int best = 0;
    double bestDistance = 0;
    for (const WarmCandidate& k : candidates) {
        if (k.x.size() != x.size()) continue;
        double d = 0;
        for (std::size_t i = 0; i < x.size(); ++i) d += (k.x[i] - x[i]) * (k.x[i] - x[i]);
        d = std::sqrt(d);
        const double tie = 1e-6 * std::max(d, bestDistance);
        const bool closer = best == 0 || d < bestDistance - tie;
        const bool asCloseAndOlder = best != 0 && std::abs(d - bestDistance) <= tie && k.evaluation < best;
        if (closer || asCloseAndOlder) {
            best = k.evaluation;
            bestDistance = d;
        }
    }
    return best;
}

std::pair<int, double> nearlyFeasibleBest(const optimize::Problem& p, const std::vector<OptimizationRecord>& values,
                                          double bestObjective, double tolerance) {
    int found = 0;
    double objective = 0, violation = 0;
    for (const OptimizationRecord& r : values) {
        if (r.kind != Kind::Values || !r.ok || r.x.size() != p.start.size()) continue;
        const double h = optimize::feasibility(p, r.x, r.constraints);
        if (h > tolerance && h <= kNearlyFeasible && r.objective < bestObjective && (found == 0 || r.objective < objective)) {
            found = r.index;
            objective = r.objective;
            violation = h;
        }
    }
    return {found, violation};
}

const char* recordKindName(Kind k) {
    switch (k) {
        case Kind::Header: return "header";
        case Kind::Values: return "values";
        case Kind::Gradient: return "gradient";
        case Kind::Iteration: return "iteration";
    }
    return "?";
}

std::string historyJsonlPath(const std::string& csv) {
    fs::path p(csv);
    p.replace_extension(".jsonl");
    return p.string();
}

namespace {
// The folder of an optimization's warm-start states, beside its CSV history.
fs::path warmStateFolder(const std::string& csv) { return fs::path(csv).replace_extension(".states"); }
}  // namespace

std::string warmStatePath(const std::string& csv, int evaluation) {
    return (warmStateFolder(csv) / (std::to_string(evaluation) + ".state")).string();
}

std::vector<OptimizationRecord> readHistory(const std::string& jsonl) {
    std::ifstream in(jsonl, std::ios::binary);
    if (!in) throw InputError("cannot read the optimization history '" + jsonl + "': " + std::strerror(errno));
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    std::vector<OptimizationRecord> records;
    std::size_t start = 0;
    int line = 0;
    while (start < text.size()) {
        const std::size_t end = text.find('\n', start);
        ++line;
        if (end == std::string::npos) break;  // incomplete last line (killed while writing): dropped
        const std::string where = "'" + jsonl + "' line " + std::to_string(line);
        try {
            records.push_back(fromJson(Json::parse(text.substr(start, end - start)), where));
        } catch (const Json::exception& e) {
            throw InputError(where + ": not a history record: " + e.what());
        }
        start = end + 1;
    }
    return records;
}

io::CaseFile evaluationCase(const CaseEvaluator& ev, int evaluation) {
    const io::CaseFile& c = ev.caseFile();
    if (!c.optimization.present) throw CaseError("'" + c.path + "': the case has no \"optimization\" section");
    if (!ev.model() || ev.variableCount() == 0) throw CaseError("'" + c.path + "': the case has no design variables");
    const std::string jsonl = historyJsonlPath(c.optimization.history);
    if (!fs::exists(jsonl)) throw InputError("'" + jsonl + "': the case's optimization history does not exist (not run yet?)");
    const OptimizationRecord* found = nullptr;
    int last = 0;
    const std::vector<OptimizationRecord> records = readHistory(jsonl);
    for (const OptimizationRecord& r : records) {
        if (r.kind != Kind::Values) continue;
        last = std::max(last, r.index);
        if (r.index == evaluation) found = &r;  // the last one: a resume that left its path rewrote it
    }
    if (!found) {
        throw CaseError(format("'%s': the history has no evaluation %d (it has %d)", jsonl.c_str(), evaluation, last));
    }
    const std::vector<ffd::DesignVariable>& vars = ev.model()->design().variables();
    const std::vector<double> scale = variableScales(c.optimization, vars);
    const std::size_t nv = vars.size();
    if (found->x.size() != nv + (c.optimization.alphaVariable ? 1 : 0)) {
        throw InputError(format("'%s': evaluation %d has %zu variables, the case %zu%s: the history belongs to another "
                                "problem",
                                jsonl.c_str(), evaluation, found->x.size(), nv,
                                c.optimization.alphaVariable ? " and alpha" : ""));
    }
    std::vector<double> v(nv);
    for (std::size_t i = 0; i < nv; ++i) v[i] = found->x[i] * scale[i];
    const double alpha = c.optimization.alphaVariable ? found->x[nv] * alphaScale(c.optimization) : c.flow.freeStream.alphaDeg;
    std::string what = found->ok ? format("%s %.8g", c.optimization.objective.c_str(), found->J)
                                 : found->status + ": " + found->message;
    return ev.designCase(v, alpha, format("evaluation %d of the optimization of %s (%s)", evaluation, c.path.c_str(),
                                          what.c_str()));
}

OptimizationSummary optimizeCase(CaseEvaluator& ev, const OptimizationOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    const io::CaseFile& c = ev.caseFile();
    const io::OptimizationCase& oc = c.optimization;
    if (!oc.present) throw CaseError("'" + c.path + "': the case has no \"optimization\" section");
    if (!c.flow.present) throw CaseError("'" + c.path + "': the optimization needs a \"flow\" section");
    if (!ev.model() || ev.variableCount() == 0) throw CaseError("'" + c.path + "': the case has no design variables to optimize");
    checkGradientFunctional(oc.objective);
    // A gradient usually follows the evaluation of its design: its mesh adjoint then reuses that
    // move's K and factors (the evaluator keeps them from here on; after another evaluation the
    // mesh adjoint assembles them again).
    ev.moveWorkspace().setKeepIncrements(true);
    const std::unique_ptr<optimize::Optimizer> optimizer = [&] {
        try {
            return optimize::makeOptimizer(oc.optimizer);
        } catch (const std::invalid_argument& e) {
            throw CaseError("'" + c.path + "': optimization.optimizer: " + e.what());
        }
    }();
    auto say = [&](const std::string& s) {
        if (o.log) o.log(s);
    };

    // The optimizer's variables.
    const ffd::FfdModel& model = *ev.model();
    const std::vector<ffd::DesignVariable>& vars = model.design().variables();
    const int nv = static_cast<int>(vars.size());
    const bool withAlpha = oc.alphaVariable;
    const int n = nv + (withAlpha ? 1 : 0);
    const std::vector<double> scale = variableScales(oc, vars);
    OptimizationSummary summary;
    optimize::Problem p;
    // Where the optimizer starts: this case's own design, or that of optimization.start_design
    // (e.g. the best design of a run on a coarser grid). The problem is this case's either way.
    const StartDesign start = startDesign(c, model, ev.caseValues());
    std::vector<double> caseStart;  // this case's own design, scaled: what min_volume "initial" means
    for (int i = 0; i < nv; ++i) {
        p.lower.push_back(vars[i].lower / scale[i]);
        p.upper.push_back(vars[i].upper / scale[i]);
        p.start.push_back(start.values[i] / scale[i]);
        caseStart.push_back(ev.caseValues()[i] / scale[i]);
        summary.names.push_back(vars[i].name);
    }
    const double alphaUnit = alphaScale(oc);
    if (withAlpha) {
        p.lower.push_back(oc.alphaLower / alphaUnit);
        p.upper.push_back(oc.alphaUpper / alphaUnit);
        p.start.push_back(start.alphaDeg / alphaUnit);
        summary.names.push_back("alpha");
    }
    if (!oc.startDesign.empty()) {
        say(format("starting from the design of '%s' (%d of %d design variables away from this case's own%s)",
                   oc.startDesign.c_str(), start.changed, nv,
                   withAlpha ? format(", alpha %.6g deg", start.alphaDeg).c_str() : ""));
    }
    auto design = [&](const std::vector<double>& u) {
        std::vector<double> v(nv);
        for (int i = 0; i < nv; ++i) v[i] = u[i] * scale[i];
        return v;
    };
    auto alphaOf = [&](const std::vector<double>& u) { return withAlpha ? u[nv] * alphaUnit : c.flow.freeStream.alphaDeg; };

    for (const ffd::LinearConstraint& lc : ev.linearConstraints()) {
        optimize::LinearRow r;
        r.name = lc.name;
        for (int i = 0; i < nv; ++i) {
            if (lc.row[i] != 0) {
                r.index.push_back(i);
                r.coefficient.push_back(lc.row[i] * scale[i]);
            }
        }
        r.lower = lc.lower;
        r.upper = lc.upper;
        if (!r.index.empty()) p.linear.push_back(std::move(r));
    }
    summary.startVolume = model.volume(design(caseStart));
    const bool volumeConstraint = c.minVolume.has_value();
    const double infinity = std::numeric_limits<double>::infinity();
    if (volumeConstraint && !(summary.startVolume > 0)) {
        // The volume is 1/3 of the flux of x out through the patches, the body closed by the
        // symmetry plane Y = 0: a shape whose patches face inward (as a CAD file may write them)
        // has a negative one. The constraint is the volume's ratio to the start's, so a bound
        // given as a number would then be met by every such shape (the ratio's sign flips), and
        // the history's volumes would read negative: the user orients the patches instead.
        throw InputError("constraints.min_volume: the case's design's enclosed volume is " + format("%.6g", summary.startVolume) +
                         " (1/3 of the flux of x through the patches, the body closed by the symmetry plane Y = 0): "
                         "its patches' normals point into the body, or it is not a half-body closed by Y = 0; "
                         "reverse the patches' orientation, or drop min_volume");
    }
    if (volumeConstraint) {
        const double minimum = std::isnan(*c.minVolume) ? summary.startVolume : *c.minVolume;
        p.nonlinear.push_back({"volume / start volume", minimum / summary.startVolume, infinity});
    }
    if (oc.liftConstraint) p.nonlinear.push_back({"CL", oc.targetCL, oc.targetCL});
    const bool gridConstraint = oc.minCornerRatio > 0;
    if (gridConstraint) p.nonlinear.push_back({"grid corner ratio (log)", std::log(oc.minCornerRatio), infinity});
    const bool bendConstraint = oc.maxWallBend > 0;
    if (bendConstraint) p.nonlinear.push_back({"wall bend (degrees, smooth max)", -infinity, oc.maxWallBend});
    // The wall's local Mach number, aggregated about the bound itself (the aggregate's terms are
    // then of order 1 where it matters).
    const bool machConstraint = oc.maxWallMach > 0;
    const adjoint::Functional wallMach =
        machConstraint ? adjoint::Functional::wallMachSum(kWallMachRho, oc.maxWallMach) : adjoint::Functional{};
    if (machConstraint) p.nonlinear.push_back({"wall Mach (smooth max)", -infinity, oc.maxWallMach});
    // Geometric constraints of the FFD model itself (exact values and gradients, no adjoint).
    std::optional<ffd::ThicknessConstraints> thickness;
    if (c.thickness.present()) {
        try {
            thickness.emplace(model, ffd::ThicknessSpec{c.thickness.stations, c.thickness.chordFractions, c.thickness.points});
        } catch (const GeometryError& e) {
            throw CaseError("'" + c.path + "': constraints.thickness: " + e.what());
        }
        for (const ffd::ThicknessPoint& tp : thickness->points()) {
            p.nonlinear.push_back({tp.name + " / baseline", c.thickness.minRatio, infinity});
        }
    }
    std::optional<ffd::LatticeJacobianBound> jacobianBound;
    if (c.minLatticeJacobian > 0) {
        try {
            jacobianBound.emplace(model);
        } catch (const GeometryError& e) {
            throw CaseError("'" + c.path + "': constraints.min_lattice_jacobian: " + e.what());
        }
        p.nonlinear.push_back({"lattice det J / baseline (smooth min)", c.minLatticeJacobian, infinity});
    }
    auto designRow = [&](const std::vector<double>& dv) {
        std::vector<double> row(n, 0.0);
        for (int i = 0; i < nv; ++i) row[i] = dv[i] * scale[i];
        return row;
    };
    const double sign = (oc.maximize ? -1.0 : 1.0) * oc.objectiveScale;
    GradientOptions go;
    go.functionals = {oc.objective};
    // The inverse design's target: read for the grid at the first evaluation (checked against it).
    const bool inverse = oc.objective == "pressure";
    adjoint::Functional mismatch;
    auto objectiveValue = [&](const FlowResult& f) {
        if (!inverse) {
            const flow::ForceCoefficients& fc = f.forces;
            return oc.objective == "CL/CD" ? fc.CL / fc.CD : adjoint::functionalValue(adjoint::functionalByName(oc.objective), fc);
        }
        if (!mismatch.targetPressure) {
            go.targetPressure = io::readWallPressureCsv(oc.targetPressure, f.mesh);
            mismatch = adjoint::Functional::pressureMismatch(go.targetPressure);
        }
        return adjoint::functionalValue(mismatch, f.mesh, f.metrics, f.x, f.q, f.residualOptions.freeStream, c.flow.reference);
    };
    if (oc.liftConstraint && oc.objective != "CL") go.functionals.push_back("CL");
    if (gridConstraint) go.cornerRatioRho = kCornerRatioRho;
    if (bendConstraint) go.wallBendRho = kWallBendRho;
    if (machConstraint) {
        go.functionals.push_back(kWallMach);
        go.wallMachRho = wallMach.rho;
        go.wallMachReference = wallMach.machReference;
    }

    // The history files.
    summary.historyCsv = oc.history;
    summary.historyJsonl = historyJsonlPath(oc.history);
    {
        fs::path it(oc.history);
        summary.iterationsCsv = (it.parent_path() / (it.stem().string() + "_iterations.csv")).string();
    }
    const fs::path stateDir = warmStateFolder(oc.history);
    if (!fs::path(oc.history).parent_path().empty()) fs::create_directories(fs::path(oc.history).parent_path());
    // The best shape's folder too, now: a missing folder found after hours of evaluations would
    // lose the shape the run was for.
    if (!c.outputGeometry.empty() && !fs::path(c.outputGeometry).parent_path().empty()) {
        fs::create_directories(fs::path(c.outputGeometry).parent_path());
    }
    // One run at a time owns a history: a second one, resumed or fresh, would interleave its
    // records with the first's or delete the warm states the first reads. Taken before the
    // history is read, replaced or appended to.
    const FileLock lock(summary.historyJsonl + ".lock");
    if (!lock.held()) {
        throw InputError("the optimization history '" + summary.historyJsonl + "' is in use by another run" +
                         (lock.owner().empty() ? std::string() : " (process " + lock.owner() + ")") +
                         ": wait for it to end, or stop it (Ctrl+C, or Stop in the GUI) and then --resume");
    }
    OptimizationRecord header;
    header.kind = Kind::Header;
    header.optimizer = oc.optimizer;
    header.objectiveName = oc.objective;
    header.names = summary.names;
    for (const optimize::ConstraintSpec& k : p.nonlinear) header.constraintNames.push_back(k.name);
    std::deque<OptimizationRecord> replay;
    std::vector<OptimizationRecord> kept;  // the records of the file, as they stay
    CsvHistory csv(summary.historyCsv, summary.iterationsCsv, summary.names);
    if (o.resume) {
        if (!fs::exists(summary.historyJsonl)) {
            throw InputError("nothing to resume: the optimization history '" + summary.historyJsonl + "' does not exist");
        }
        kept = readHistory(summary.historyJsonl);
        if (kept.empty() || kept.front().kind != Kind::Header) {
            throw InputError("'" + summary.historyJsonl + "' does not start with a history header");
        }
        const OptimizationRecord& h = kept.front();
        auto list = [](const std::vector<std::string>& v) {
            std::string s;
            for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
            return s.empty() ? std::string("none") : s;
        };
        if (h.names != header.names || h.optimizer != header.optimizer || h.objectiveName != header.objectiveName ||
            h.constraintNames != header.constraintNames) {
            throw InputError("'" + summary.historyJsonl + "' was written for another problem (optimizer " + h.optimizer +
                             ", objective " + h.objectiveName + ", " + std::to_string(h.names.size()) +
                             " variables, constraints: " + list(h.constraintNames) + "); the case now has optimizer " +
                             header.optimizer + ", objective " + header.objectiveName + ", " +
                             std::to_string(header.names.size()) + " variables, constraints: " + list(header.constraintNames) +
                             " (start over with --fresh)");
        }
        for (OptimizationRecord& r : kept) {
            // A history written before the planform was recorded: computed from the design (the
            // shape alone, no flow), so the resumed run's CSV has it for every evaluation.
            if (r.kind == Kind::Values && !(r.planform.projectedArea > 0) && r.x.size() == static_cast<std::size_t>(n))
                r.planform = planformOf(model.deform(design(r.x)));
            if (r.kind == Kind::Values || r.kind == Kind::Gradient) replay.push_back(r);
        }
        say(format("resuming: %.0f evaluations and %.0f gradients in '%s' are replayed, not solved again",
                   static_cast<double>(std::count_if(replay.begin(), replay.end(), [](const auto& r) { return r.kind == Kind::Values; })),
                   static_cast<double>(std::count_if(replay.begin(), replay.end(), [](const auto& r) { return r.kind == Kind::Gradient; })),
                   summary.historyJsonl.c_str()));
    } else {
        if (fs::exists(summary.historyJsonl) && fs::file_size(summary.historyJsonl) > 0 && !o.fresh) {
            throw InputError("the optimization history '" + summary.historyJsonl +
                             "' exists: resume it (--resume), or start over and replace it (--fresh)");
        }
        fs::remove_all(stateDir);
        kept.push_back(header);
    }
    fs::create_directories(stateDir);
    // The file as it stays (a cut last line dropped), then appended to.
    auto rewriteHistory = [&] {
        std::string text;
        for (const OptimizationRecord& r : kept) text += toJson(r).dump() + "\n";
        writeTextAtomically(summary.historyJsonl, text, "optimization history");
    };
    rewriteHistory();
    csv.rewrite(kept);
    if (!oc.iterations.empty()) fs::create_directories(oc.iterations);

    auto statePath = [&](int index) { return warmStatePath(oc.history, index); };
    int evaluations = 0, gradients = 0;
    int lastOk = 0;                 // the last accepted evaluation
    std::map<int, double> entropyOf;  // accepted evaluation -> its largest |s - s_inf|
                                      // (optimization.max_entropy_rise)
    std::map<int, int> warmFromOf;  // evaluation -> the evaluation its flow started from
    std::vector<WarmCandidate> warmCandidates;  // accepted evaluations whose state is kept, oldest first
    int iterate = 0, previousIterate = 0;  // the evaluations at the optimizer's last two iterates
    std::shared_ptr<Evaluation> last;  // the last evaluation run here (for its gradient)
    std::vector<double> lastX;
    bool replaying = !replay.empty();
    auto record = [&](OptimizationRecord& r) {
        if (o.onRecord) o.onRecord(r);
        if (r.replayed) return;
        appendLine(summary.historyJsonl, toJson(r).dump(), "optimization history");
        csv.append(r);
    };
    // While replaying, an iteration the file holds at the same point is replayed; from the first
    // one it does not hold there (this build numbers the iterations otherwise, e.g. judges
    // SLSQP's trials otherwise) on, every iteration waits here until the replay ends, when the
    // file's iterations from that number on are dropped as stale and these are written in order.
    std::vector<OptimizationRecord> unrecordedIterations;
    int replayedIterations = -1;  // the last iteration replayed
    auto stopReplay = [&](const char* why) {
        if (!replaying) return;
        replaying = false;
        const int stale = unrecordedIterations.empty() ? replayedIterations + 1 : unrecordedIterations.front().index;
        const auto before = kept.size();
        kept.erase(std::remove_if(kept.begin(), kept.end(),
                                  [&](const OptimizationRecord& r) { return r.kind == Kind::Iteration && r.index >= stale; }),
                   kept.end());
        const bool rewrite = kept.size() != before || !replay.empty();
        if (!replay.empty()) {
            // The optimizer left the recorded path (e.g. another build): the rest no longer applies.
            say(std::string("the optimizer left the recorded path (") + why + "): the " + std::to_string(replay.size()) +
                " records after it are discarded and solved anew");
            // The records from the first one not replayed on: the values and gradients left in
            // `replay`, and the iterations recorded between them (they are not in `replay`).
            std::size_t cut = kept.size(), removed = 0;
            while (cut > 0 && removed < replay.size()) {
                --cut;
                if (kept[cut].kind == Kind::Values || kept[cut].kind == Kind::Gradient) ++removed;
            }
            kept.resize(cut);
            replay.clear();
        }
        if (rewrite) {
            rewriteHistory();
            csv.rewrite(kept);
        }
        for (OptimizationRecord& r : unrecordedIterations) {
            appendLine(summary.historyJsonl, toJson(r).dump(), "optimization history");
            csv.append(r);
        }
        unrecordedIterations.clear();
    };
    // An accepted evaluation's state joins the candidates; the oldest beyond kKeptStates go (their
    // files too), except the optimizer's last two iterates and the state this evaluation started
    // from (a resume that has its values but not its gradient solves it again from there). The
    // same happens when a resumed run replays the record, so the candidates, and with them every
    // warm start, are the same.
    auto keepState = [&](int index, const std::vector<double>& u, int from) {
        warmCandidates.push_back({index, u});
        std::size_t extra = warmCandidates.size() > kKeptStates ? warmCandidates.size() - kKeptStates : 0;
        for (auto k = warmCandidates.begin(); extra > 0 && k != warmCandidates.end();) {
            if (k->evaluation == iterate || k->evaluation == previousIterate || k->evaluation == from) {
                ++k;
                continue;
            }
            std::error_code ignored;
            fs::remove(statePath(k->evaluation), ignored);
            k = warmCandidates.erase(k);
            --extra;
        }
    };
    // Gives the evaluator the state of the design the step to u came from: of the optimizer's last
    // two iterates, the one closer to u (else, before the first iterate or when its state is gone,
    // that of the kept evaluation closest to u); returns that evaluation (0: none, a cold start).
    // The previous iterate counts because a line search can run from it when an optimizer reports
    // a trial as its iterate before the line search rejects it: the next trials then lie between
    // the two, closer to the previous one. (SLSQP's driver did so until the thirty-sixth session;
    // on its Figure 4 run six such trials, within 3e-4 to 3e-9 of the previous iterate, all
    // started from the rejected trial's flow and stayed on its branch, L/D 1.945 against the
    // previous iterate's 2.028, so the line search could not succeed.) A candidate whose
    // file is gone (a history of an older build kept only the newest two) is dropped; when none
    // is left, the newest state in the folder, a nearby converged flow of a discarded evaluation,
    // is a better start than the free stream.
    auto warmStartFor = [&](const std::vector<double>& u) {
        const bool hadCandidates = !warmCandidates.empty();
        while (!warmCandidates.empty()) {
            const bool atIterate = std::any_of(warmCandidates.begin(), warmCandidates.end(),
                                               [&](const WarmCandidate& k) { return k.evaluation == iterate; });
            std::vector<WarmCandidate> base;
            if (atIterate) {
                std::copy_if(warmCandidates.begin(), warmCandidates.end(), std::back_inserter(base),
                             [&](const WarmCandidate& k) { return k.evaluation == iterate || k.evaluation == previousIterate; });
            }
            const int from = closestWarmStart(atIterate ? base : warmCandidates, u);
            std::vector<double> q = io::readWarmState(statePath(from));
            if (!q.empty()) {
                ev.setWarmStart(std::move(q));
                return from;
            }
            warmCandidates.erase(std::find_if(warmCandidates.begin(), warmCandidates.end(),
                                              [&](const WarmCandidate& k) { return k.evaluation == from; }));
            if (from == iterate) iterate = 0;
        }
        ev.forgetWarmStart();
        if (!hadCandidates) return 0;
        int newest = 0;
        std::vector<double> q;
        for (const auto& entry : fs::directory_iterator(stateDir)) {
            if (entry.path().extension() != ".state") continue;
            const int k = std::atoi(entry.path().stem().string().c_str());
            if (k <= newest) continue;
            std::vector<double> other = io::readWarmState(entry.path().string());
            if (other.empty()) continue;
            newest = k;
            q = std::move(other);
        }
        if (newest > 0) {
            say(format("evaluation %d's flow state was not kept: the next flow starts from that of the discarded "
                       "evaluation %d",
                       lastOk, newest));
            ev.setWarmStart(std::move(q));
        }
        return newest;
    };
    auto evaluateAt = [&](const std::vector<double>& u) {
        EvaluationRequest req;
        req.alphaDeg = alphaOf(u);
        if (!ev.lastConvergedState().empty()) {
            // A step from an accepted design (optimization.warm_start_fallback): what a stalled
            // warm start may try before the evaluation fails and the optimizer cuts the step.
            req.coldRetry = oc.warmStartFallback != "none";
            req.dissipationRetry = oc.warmStartFallback == "continuation";
            req.stallModes = c.flow.stallModes && oc.stallModes;
            if (oc.warmStartIterations > 0) req.warmIterations = oc.warmStartIterations;
        }
        return std::make_shared<Evaluation>(ev.evaluate(design(u), req, o.progress, o.cancel));
    };

    p.values = [&](const std::vector<double>& u) -> optimize::Values {
        optimize::Values out;
        if (replaying && !replay.empty() && replay.front().kind == Kind::Values && sameBits(replay.front().x, u)) {
            OptimizationRecord r = replay.front();
            replay.pop_front();
            r.replayed = true;
            ++summary.replayedEvaluations;
            evaluations = r.index;
            if (r.ok) {
                warmFromOf[r.index] = r.warmFrom;
                lastOk = r.index;
                entropyOf[r.index] = r.maxEntropy;
                keepState(r.index, r.x, r.warmFrom);
            }
            if (r.warmFrom == 0 && summary.coldFlowIterations == 0) summary.coldFlowIterations = r.flowIterations;
            record(r);
            out.ok = r.ok;
            out.message = r.ok ? std::string() : r.status + ": " + r.message;  // as when it was run
            out.objective = r.objective;
            out.constraints = r.constraints;
            return out;
        }
        stopReplay("another evaluation point");
        OptimizationRecord r;
        r.kind = Kind::Values;
        r.index = ++evaluations;
        r.x = u;
        r.alphaDeg = alphaOf(u);
        r.warmFrom = warmStartFor(u);
        const auto t = std::chrono::steady_clock::now();
        std::shared_ptr<Evaluation> e = evaluateAt(u);
        r.seconds = since(t);
        if (e->status == EvaluationStatus::Cancelled) {
            --evaluations;  // not recorded: a resumed run evaluates it again
            out.ok = false;
            out.message = "cancelled";
            return out;
        }
        const std::vector<double> v = design(u);
        r.volume = model.volume(v);
        r.planform = planformOf(e->shape);
        // A converged flow whose entropy error is beyond the case's bound, or that jumped from that
        // of the design it started from by more than the case allows, is no answer to climb on.
        const double entropy = e->ok() ? std::abs(e->flow->maxEntropy.value) : 0.0;
        const bool beyondLevel = e->ok() && oc.maxEntropy > 0 && entropy > oc.maxEntropy;
        const int base = entropyOf.count(r.warmFrom) ? r.warmFrom : 0;  // the design this flow started from
        const double baseEntropy = base > 0 ? entropyOf[base] : 0.0;
        const bool jumped = e->ok() && !beyondLevel && oc.maxEntropyRise > 0 && baseEntropy > 0 &&
                            entropy > oc.maxEntropyRise * baseEntropy;
        const bool unresolved = beyondLevel || jumped;
        r.status = unresolved ? kUnresolved : e->ok() ? "ok" : evaluationStatusName(e->status);
        if (e->mesh && !e->mesh->grids.empty()) r.wallBend = e->mesh->wallBend.degrees;
        if (e->flow && e->flow->modesChecked) r.growingMode = e->flow->modes.growthRate();
        if (e->flow) {
            // A warm start solved again from the free stream (CaseEvaluator's cold retry) counts both.
            r.flowIterations = e->flow->totalIterations();
            if (e->flow->warmStarted) {
                ++summary.warmStarts;
                summary.meanWarmFlowIterations += r.flowIterations;
            } else if (summary.coldFlowIterations == 0) {
                summary.coldFlowIterations = r.flowIterations;
            }
        }
        if (e->ok()) {
            // Accepted or refused, the flow converged: its forces go to the history.
            const flow::ForceCoefficients& f = e->flow->forces;
            r.CL = f.CL;
            r.CD = f.CD;
            r.CM = f.CM;
            r.maxMach = e->flow->maxMach.value;
            r.maxEntropy = entropy;
        }
        if (e->ok() && !unresolved) {
            r.J = objectiveValue(*e->flow);
            r.objective = sign * r.J;
            if (volumeConstraint) r.constraints.push_back(r.volume / summary.startVolume);
            if (oc.liftConstraint) r.constraints.push_back(r.CL);
            if (gridConstraint) {
                r.cornerRatio = mesh::cornerRatioSmoothMin(e->mesh->grids, ev.baselineGrids(), kCornerRatioRho);
                r.constraints.push_back(r.cornerRatio);
            }
            if (bendConstraint) r.constraints.push_back(mesh::wallBendSmoothMax(e->mesh->grids, mesh::wallFaces(e->mesh->control), kWallBendRho));
            if (machConstraint) {
                const FlowResult& fl = *e->flow;
                r.constraints.push_back(adjoint::wallMachSmoothMax(
                    wallMach, adjoint::functionalValue(wallMach, fl.mesh, fl.metrics, fl.x, fl.q, fl.residualOptions.freeStream,
                                                       c.flow.reference)));
            }
            if (thickness) {
                for (double x : thickness->ratios(v)) r.constraints.push_back(x);
            }
            if (jacobianBound) r.constraints.push_back(jacobianBound->value(v));
            io::writeWarmState(statePath(r.index), e->flow->q);
            warmFromOf[r.index] = r.warmFrom;
            lastOk = r.index;
            entropyOf[r.index] = entropy;
            keepState(r.index, u, r.warmFrom);
            last = e;
            lastX = u;
        } else if (unresolved) {
            // Not a candidate for warm starts, and the evaluator lets it go too: no later step
            // starts on this flow's branch.
            ev.forgetWarmStart();
            const FlowLocation& s = e->flow->maxEntropy;
            const std::string bound =
                beyondLevel ? format("optimization.max_entropy %.3g", oc.maxEntropy)
                            : format("%.3g times the %.3g of evaluation %d, the design this flow started from; "
                                     "optimization.max_entropy_rise %.3g",
                                     entropy / baseEntropy, baseEntropy, base, oc.maxEntropyRise);
            r.ok = false;
            r.message = format("the flow converged, but its entropy error |s - s_inf| reaches %.3g (%s) at block %d "
                               "'%s' node (%d, %d, %d) at (%.4g, %.4g, %.4g), %s: %s, not an answer to optimize on "
                               "(CL %.6g, CD %.6g, max Mach %.3g); the step is cut and the state is not used for "
                               "warm starts",
                               entropy, bound.c_str(), s.block, s.blockName.c_str(), s.node[0], s.node[1], s.node[2],
                               s.x[0], s.x[1], s.x[2], s.boundary.c_str(),
                               beyondLevel ? "a separated or unresolved flow" : "a jump to another steady state (e.g. a separated flow)",
                               r.CL, r.CD, r.maxMach);
        } else {
            r.ok = false;
            r.message = e->message;
            if (e->flow && (e->flow->warmStarted || e->flow->coldRetry()) && oc.warmStartFallback != "continuation") {
                r.message += format(" (a warm start from evaluation %d; optimization.warm_start_fallback %s: %s)", r.warmFrom,
                                    oc.warmStartFallback.c_str(),
                                    oc.warmStartFallback == "none" ? "not solved again, the step is cut"
                                                                   : "no continuation in the dissipation");
            }
        }
        if (o.onEvaluation) o.onEvaluation(r, *e);
        record(r);
        out.ok = r.ok;
        out.message = r.ok ? std::string() : r.status + ": " + r.message;
        out.objective = r.objective;
        out.constraints = r.constraints;
        return out;
    };

    p.gradients = [&](const std::vector<double>& u) -> optimize::Gradients {
        optimize::Gradients out;
        if (replaying && !replay.empty() && replay.front().kind == Kind::Gradient && sameBits(replay.front().x, u)) {
            OptimizationRecord r = replay.front();
            replay.pop_front();
            r.replayed = true;
            ++summary.replayedGradients;
            gradients = r.index;
            record(r);
            out.ok = r.ok;
            out.message = r.message;
            out.objective = r.dObjective;
            out.constraints = r.dConstraints;
            return out;
        }
        stopReplay("another gradient point");
        OptimizationRecord r;
        r.kind = Kind::Gradient;
        r.index = ++gradients;
        r.x = u;
        const auto t = std::chrono::steady_clock::now();
        std::shared_ptr<Evaluation> e = last;
        if (!e || !sameBits(lastX, u)) {
            // Not the last evaluation here (e.g. its values were replayed): solve it again from the
            // state it started from (each evaluation sets its own warm start, so nothing is disturbed).
            const OptimizationRecord* v = csv.valuesAt(u);
            const int from = v && warmFromOf.count(v->index) ? warmFromOf[v->index] : 0;
            if (from > 0) ev.setWarmStart(io::readWarmState(statePath(from)));
            else ev.forgetWarmStart();
            e = evaluateAt(u);
        }
        if (e->ok() && inverse && !mismatch.targetPressure) (void)objectiveValue(*e->flow);  // values were replayed
        if (!e->ok()) {
            r.ok = false;
            r.message = std::string("the evaluation for the gradient failed: ") + evaluationStatusName(e->status) + ": " + e->message;
        } else {
            const GradientResult g = computeGradient(ev, *e, go);
            for (const auto& a : g.adjoints) r.adjointIterations += static_cast<int>(a.iterations);
            if (!g.ok) {
                r.ok = false;
                r.message = g.message;
            } else {
                const FunctionalGradient& fo = *g.find(oc.objective);
                r.dObjective.assign(n, 0.0);
                for (int i = 0; i < nv; ++i) r.dObjective[i] = sign * fo.dv[i] * scale[i];
                if (withAlpha) r.dObjective[nv] = sign * fo.dalpha * alphaUnit;
                if (volumeConstraint) {
                    const std::vector<double> dV = model.volumeGradient(design(u));
                    std::vector<double> row(n, 0.0);
                    for (int i = 0; i < nv; ++i) row[i] = dV[i] * scale[i] / summary.startVolume;
                    r.dConstraints.push_back(row);
                }
                if (oc.liftConstraint) {
                    const FunctionalGradient& fl = *g.find("CL");
                    std::vector<double> row(n, 0.0);
                    for (int i = 0; i < nv; ++i) row[i] = fl.dv[i] * scale[i];
                    if (withAlpha) row[nv] = fl.dalpha * alphaUnit;
                    r.dConstraints.push_back(row);
                }
                if (gridConstraint) {
                    const FunctionalGradient& fr = *g.find(kCornerRatio);
                    std::vector<double> row(n, 0.0);
                    for (int i = 0; i < nv; ++i) row[i] = fr.dv[i] * scale[i];
                    r.dConstraints.push_back(row);
                }
                if (bendConstraint) r.dConstraints.push_back(designRow(g.find(kWallBend)->dv));
                if (machConstraint) {
                    const FunctionalGradient& fm = *g.find(kWallMach);
                    std::vector<double> row = designRow(fm.dv);
                    if (withAlpha) row[nv] = fm.dalpha * alphaUnit;
                    r.dConstraints.push_back(row);
                }
                if (thickness) {
                    for (const std::vector<double>& dt : thickness->ratioGradients(design(u))) r.dConstraints.push_back(designRow(dt));
                }
                if (jacobianBound) r.dConstraints.push_back(designRow(jacobianBound->gradient(design(u))));
            }
        }
        r.seconds = since(t);
        record(r);
        out.ok = r.ok;
        out.message = r.message;
        out.objective = r.dObjective;
        out.constraints = r.dConstraints;
        return out;
    };

    // The shape stage alone at u, written as <stem>.igs and <stem>.vtm; returns the shape.
    auto writeShape = [&](const std::vector<double>& u, const std::string& stem) {
        EvaluationRequest req;
        req.mesh = false;
        req.flow = false;
        Evaluation e = ev.evaluate(design(u), req);
        saveGeometry(e.shape, stem + ".igs");
        io::writeVtm(stem + ".vtm", io::geometryBlocks(e.shape, &ev.baseline(), e.lattices, nullptr));
        return std::move(e.shape);
    };

    optimize::Settings s;
    s.optimalityTolerance = oc.optimalityTolerance;
    s.feasibilityTolerance = oc.feasibilityTolerance;
    s.maxIterations = oc.maxIterations;
    s.maxEvaluations = oc.maxEvaluations;
    s.cancel = o.cancel;
    s.log = o.log;
    s.onIteration = [&](const optimize::Iteration& it) {
        OptimizationRecord r;
        r.kind = Kind::Iteration;
        r.index = it.iteration;
        r.x = it.x;
        r.evaluations = it.evaluations;
        r.gradients = it.gradients;
        r.objective = it.objective;
        r.optimality = it.optimality;
        r.feasibility = it.feasibility;
        if (replaying) {
            r.replayed = unrecordedIterations.empty() && std::any_of(kept.begin(), kept.end(), [&](const OptimizationRecord& k) {
                return k.kind == Kind::Iteration && k.index == it.iteration && sameBits(k.x, it.x);
            });
            if (r.replayed) replayedIterations = it.iteration;
        }
        if (replaying && !r.replayed) {
            if (o.onRecord) o.onRecord(r);
            unrecordedIterations.push_back(r);
        } else {
            record(r);
        }
        const OptimizationRecord* v = csv.valuesAt(it.x);
        // The iterate's evaluation is the newest kept state at its point. Not csv.valuesAt: on a
        // resume that leaves its recorded path, it still holds the records about to be discarded,
        // whose numbers the next evaluations take.
        int at = 0;
        for (const WarmCandidate& k : warmCandidates) {
            if (sameBits(k.x, it.x)) at = k.evaluation;
        }
        if (at != iterate) {
            previousIterate = iterate;
            iterate = at;
        }
        say(format("iteration %.0f: %s %.8g, optimality %.2e, feasibility %.2e, CL %.5f, CD %.5f (%.0f evaluations)%s",
                   static_cast<double>(it.iteration), oc.objective.c_str(), v ? v->J : kNaN, it.optimality, it.feasibility,
                   v ? v->CL : kNaN, v ? v->CD : kNaN, static_cast<double>(it.evaluations), r.replayed ? " [replayed]" : ""));
        if (!oc.iterations.empty() && !r.replayed) {
            writeShape(it.x, (fs::path(oc.iterations) / format("iteration_%03.0f", static_cast<double>(it.iteration))).string());
        }
    };
    p.check();
    say(format("%s: %s %s over %.0f variables, %.0f linear and %.0f nonlinear constraints", optimizer->name().c_str(),
               oc.maximize ? "maximize" : "minimize", oc.objective.c_str(), static_cast<double>(n),
               static_cast<double>(p.linear.size()), static_cast<double>(p.nonlinear.size())));
    summary.result = optimizer->minimize(p, s);
    stopReplay("the optimizer stopped");

    // The best design: its forces from the history, its shape written out.
    const std::vector<double>& best = summary.result.x;
    summary.values = design(best);
    summary.alphaDeg = alphaOf(best);
    summary.volume = model.volume(summary.values);
    summary.startPlanform = planformOf(model.deform(design(p.start)));
    const OptimizationRecord* bestRecord = csv.valuesAt(best);
    if (bestRecord) {
        summary.bestEvaluation = bestRecord->index;
        summary.J = bestRecord->J;
        summary.forces.CL = bestRecord->CL;
        summary.forces.CD = bestRecord->CD;
        summary.forces.CM = bestRecord->CM;
    }
    {
        std::vector<OptimizationRecord> values;
        for (const auto& [index, r] : csv.values()) values.push_back(r);
        const auto [k, h] = nearlyFeasibleBest(p, values, bestRecord ? bestRecord->objective : kInfinity, oc.feasibilityTolerance);
        if (const OptimizationRecord* r = k > 0 ? &csv.values().at(k) : nullptr) {
            summary.nearlyFeasibleEvaluation = k;
            summary.nearlyFeasibleObjective = r->objective;
            summary.nearlyFeasibleJ = r->J;
            summary.nearlyFeasibleInfeasibility = h;
        }
    }
    if (summary.warmStarts > 0) summary.meanWarmFlowIterations /= summary.warmStarts;
    {
        fs::path stem(summary.historyCsv);
        const std::string bestStem = (stem.parent_path() / (stem.stem().string() + "_best")).string();
        const geometry::PatchSet shape = writeShape(best, bestStem);
        summary.planform = planformOf(shape);
        summary.finalGeometry = bestStem + ".igs";
        if (!c.outputGeometry.empty()) saveGeometry(shape, c.outputGeometry);
    }
    summary.seconds = since(t0);
    return summary;
}

}  // namespace aero::study
