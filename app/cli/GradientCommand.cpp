// aeroform-cli gradient CASE: J and dJ/dv of the case's functionals at the case's design, through
// the discrete adjoint (study/Gradient.h), with what each stage cost.
// aeroform-cli gradient-check CASE: the paper's Figure 3a - the adjoint's directional derivative
// D_z J (z_i = sign(dJ/dv_i)) against centred differences of complete evaluations over a range of
// steps, for all variables and for each variable group (and alpha) alone; CSV, SVG plot, and exit
// code 1 when the best agreement is worse than the tolerance.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/CliSupport.h"
#include "cli/SvgPlot.h"
#include "common/AtomicFile.h"
#include "common/Format.h"
#include "common/Memory.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"
#include "study/Gradient.h"

namespace aero::app {

namespace {

const char* kGradientHelp =
    "usage: aeroform-cli gradient CASE.json [--functionals LIST] [--csv FILE] [--json]\n"
    "\n"
    "Evaluates the case at its design (shape, mesh movement, flow) and computes the gradient of\n"
    "each functional with respect to every design variable and the angle of attack by the discrete\n"
    "adjoint: one flow adjoint per functional (CL/CD none when CL and CD are asked for too: the\n"
    "quotient rule on theirs), the grid sensitivities, the mesh adjoint through the\n"
    "elasticity increments and the FFD chain. The cost does not depend on the number of variables.\n"
    "\n"
    "  --functionals LIST  comma-separated: CL, CD, CM, CY, CL/CD, wall_mach (default CL,CD,CL/CD);\n"
    "                      wall_mach is the smooth maximum of the wall's local Mach number that\n"
    "                      optimization.max_wall_mach bounds (about that bound, or 1 without one)\n"
    "  --csv FILE          one row per design variable (name, value, one column per functional)\n"
    "  --json              the values, gradients and stage times as JSON on stdout\n"
    "  --help              this text\n"
    "Exit 0 on success, 1 when the design, the flow or an adjoint fails (the reason is printed),\n"
    "2 usage error.\n";

const char* kCheckHelp =
    "usage: aeroform-cli gradient-check CASE.json [--functional NAME] [--eps-range HI:LO] [--groups]\n"
    "                                              [--tolerance T] [--csv FILE] [--plot FILE.svg] [--json]\n"
    "\n"
    "The paper's gradient check (Figure 3a): the adjoint's directional derivative D_z J with\n"
    "z_i = sign(dJ/dv_i) against centred differences (J(v + eps z) - J(v - eps z)) / (2 eps) of\n"
    "complete evaluations, for eps from HI down to LO by decades. The flow and the mesh movement are\n"
    "solved to 1e-12 and 1e-14 (or the case's tighter tolerances) so the differences resolve small\n"
    "steps. With --groups each variable kind (translations, section scalings, tapers, point\n"
    "coordinates) and the angle of attack are checked alone too, so a wrong term cannot hide behind\n"
    "a right sum.\n"
    "\n"
    "  --functional NAME  CL, CD, CM, CY or CL/CD (default CL/CD)\n"
    "  --eps-range HI:LO  steps (default 1e-1:1e-8)\n"
    "  --groups           also each variable group and alpha alone\n"
    "  --tolerance T      the best relative error every check must reach (default 1e-6)\n"
    "  --csv FILE         the table (check, eps, J+, J-, centred difference, adjoint, relative error)\n"
    "  --plot FILE.svg    relative error against eps, log-log, one line per check\n"
    "  --json             the table as JSON on stdout\n"
    "Exit 0 when every check reaches the tolerance, 1 otherwise or on failure, 2 usage error.\n";

void say(const char* cmd, const std::string& s) { std::fprintf(stderr, "[%s] %s\n", cmd, s.c_str()); }

// Progress of one evaluation on stderr: the stage messages and every tenth flow iteration.
study::ProgressFn evaluationProgress(const char* cmd, bool quiet) {
    return [cmd, quiet](const study::Progress& p) {
        if (quiet) return;
        if (!p.iteration) {
            if (!p.message.empty()) say(cmd, p.message);
            return;
        }
        const flow::FlowIteration& it = *p.iteration;
        if (it.rejected.empty() && (it.iteration % 10 == 0 || it.iteration <= 1)) {
            say(cmd, format("flow iteration %d: relative residual %.3e, CFL %.3g, %.1f s", it.iteration, it.relativeResidual,
                         it.cfl, it.seconds));
        }
    };
}

study::Evaluation evaluateOrThrow(study::CaseEvaluator& ev, const std::vector<double>& v, const char* cmd, bool quiet,
                                  const std::string& what) {
    study::Evaluation e = ev.evaluate(v, {}, evaluationProgress(cmd, quiet));
    if (!e.ok()) {
        throw Error(what + ": " + study::evaluationStatusName(e.status) + ": " + e.message);
    }
    return e;
}

double functionalOf(const std::string& name, const flow::ForceCoefficients& f) {
    if (name == "CL/CD") return f.CL / f.CD;
    return adjoint::functionalValue(adjoint::functionalByName(name), f);
}

}  // namespace

int runGradient(const std::string& casePath, const std::vector<std::string>& names, const std::string& csvPath, bool json) {
    return guarded("gradient", [&] {
        const char* cmd = "gradient";
        const io::CaseFile c = io::readCase(casePath);
        if (!c.flow.present) throw CaseError("'" + casePath + "': the case has no \"flow\" section (the functionals need a flow)");
        for (const std::string& n : names) study::checkGradientFunctional(n);
        study::CaseEvaluator ev(c, loadPatchSet(c.geometry), [&](const std::string& s) { say(cmd, s); });
        ev.moveWorkspace().setKeepIncrements(true);  // the mesh adjoint reuses the move's K and factors
        const study::Evaluation e = evaluateOrThrow(ev, ev.caseValues(), cmd, false, "the case's design");
        say(cmd, format("flow converged: CL %.6f, CD %.6f, %d iterations, %.1f s", e.flow->forces.CL, e.flow->forces.CD,
                     e.flow->report.iterations, e.secondsFlow));
        study::GradientOptions o;
        o.functionals = names;
        o.wallMachRho = study::kWallMachRho;
        o.wallMachReference = c.optimization.maxWallMach > 0 ? c.optimization.maxWallMach : 1.0;
        const study::GradientResult g = study::computeGradient(ev, e, o, [&](const std::string& s) { say(cmd, s); });
        if (!g.ok) throw Error(g.message);
        const std::vector<ffd::DesignVariable> vars =
            ev.model() ? ev.model()->design().variables() : std::vector<ffd::DesignVariable>();
        const std::vector<double>& v = ev.caseValues();
        if (!csvPath.empty()) {
            std::ostringstream s;
            s << "variable,value";
            for (const auto& f : g.functionals) s << ",d" << f.name;
            s << "\n";
            s.precision(17);
            for (std::size_t i = 0; i < vars.size(); ++i) {
                s << vars[i].name << "," << v[i];
                for (const auto& f : g.functionals) s << "," << f.dv[i];
                s << "\n";
            }
            s << "alpha_deg," << c.flow.freeStream.alphaDeg;
            for (const auto& f : g.functionals) s << "," << f.dalpha;
            s << "\n";
            writeTextAtomically(csvPath, s.str(), "CSV file");
            say(cmd, "wrote " + csvPath);
        }
        if (json) {
            nlohmann::ordered_json j;
            j["case"] = casePath;
            j["variables"] = vars.size();
            nlohmann::ordered_json fs = nlohmann::ordered_json::array();
            for (const auto& f : g.functionals) {
                nlohmann::ordered_json jf;
                jf["name"] = f.name;
                jf["value"] = f.value;
                jf["dalpha_per_degree"] = f.dalpha;
                nlohmann::ordered_json grad = nlohmann::ordered_json::object();
                for (std::size_t i = 0; i < vars.size(); ++i) grad[vars[i].name] = f.dv[i];
                jf["gradient"] = grad;
                fs.push_back(jf);
            }
            j["functionals"] = fs;
            j["seconds"] = {{"flow", e.secondsFlow},
                            {"linearization", g.secondsLinearization},
                            {"flow_adjoint", g.secondsAdjoint},
                            {"grid_sensitivity", g.secondsGrid},
                            {"mesh_adjoint", g.secondsMesh},
                            {"chain", g.secondsChain},
                            {"gradient", g.seconds()}};
            j["stored_increments_mb"] = g.historyBytes / 1e6;
            j["kept_stiffness_mb"] = g.meshAdjoint.keptBytes / 1e6;  // 0 when the mesh adjoint assembled them again
            j["mesh_adjoint_reused_increments"] = g.meshAdjoint.reusedIncrements;
            j["peak_memory_mb"] = peakMemoryMb();
            std::printf("%s\n", j.dump(2).c_str());
            return kOk;
        }
        std::printf("%-24s %14s", "variable", "value");
        for (const auto& f : g.functionals) std::printf(" %16s", ("d" + f.name).c_str());
        std::printf("\n");
        for (std::size_t i = 0; i < vars.size(); ++i) {
            std::printf("%-24s %14.6g", vars[i].name.c_str(), v[i]);
            for (const auto& f : g.functionals) std::printf(" %16.8e", f.dv[i]);
            std::printf("\n");
        }
        std::printf("%-24s %14.6g", "alpha (per degree)", c.flow.freeStream.alphaDeg);
        for (const auto& f : g.functionals) std::printf(" %16.8e", f.dalpha);
        std::printf("\n\n");
        for (const auto& f : g.functionals) std::printf("%-6s = %.10g\n", f.name.c_str(), f.value);
        std::printf("\nflow %.1f s; gradient %.1f s (linearization %.1f, flow adjoint %.1f, grid sensitivities %.1f, "
                    "mesh adjoint %.1f, chain %.2f); peak memory %.0f MB\n",
                    e.secondsFlow, g.seconds(), g.secondsLinearization, g.secondsAdjoint, g.secondsGrid, g.secondsMesh,
                    g.secondsChain, peakMemoryMb());
        return kOk;
    });
}

int runGradientCheck(const std::string& casePath, const std::string& name, double hi, double lo, bool groups,
                     double tolerance, const std::string& csvPath, const std::string& plotPath, bool json) {
    return guarded("gradient-check", [&] {
        const char* cmd = "gradient-check";
        io::CaseFile c = io::readCase(casePath);
        if (!c.flow.present) throw CaseError("'" + casePath + "': the case has no \"flow\" section (the functionals need a flow)");
        study::checkGradientFunctional(name);
        c.flow.newton.relativeTolerance = std::min(c.flow.newton.relativeTolerance, 1e-12);
        c.mesh.elasticity.tolerance = std::min(c.mesh.elasticity.tolerance, 1e-14);
        c.outputFlowVtk.clear();
        c.outputResidualCsv.clear();
        c.outputRestart.clear();
        say(cmd, format("flow solved to %.0e of the initial residual, mesh movement to %.0e", c.flow.newton.relativeTolerance,
                     c.mesh.elasticity.tolerance));
        const geometry::PatchSet geometry = loadPatchSet(c.geometry);
        study::CaseEvaluator ev(c, geometry, [&](const std::string& s) { say(cmd, s); });
        ev.moveWorkspace().setKeepIncrements(true);  // the mesh adjoint reuses the move's K and factors
        const std::vector<double> v0 = ev.caseValues();
        const study::Evaluation e = evaluateOrThrow(ev, v0, cmd, false, "the case's design");
        study::GradientOptions o;
        o.functionals = {name};
        const study::GradientResult g = study::computeGradient(ev, e, o, [&](const std::string& s) { say(cmd, s); });
        if (!g.ok) throw Error(g.message);
        const study::FunctionalGradient& grad = g.functionals.front();

        // The checks: all variables, then (with --groups) each kind alone, then alpha.
        struct Check {
            std::string label;
            std::vector<double> z;  // empty: alpha
        };
        std::vector<Check> checks;
        const std::size_t n = v0.size();
        auto signs = [&](auto&& keep) {
            std::vector<double> z(n, 0.0);
            for (std::size_t i = 0; i < n; ++i) {
                if (keep(i)) z[i] = grad.dv[i] > 0 ? 1.0 : (grad.dv[i] < 0 ? -1.0 : 0.0);
            }
            return z;
        };
        if (n > 0) checks.push_back({"all variables", signs([](std::size_t) { return true; })});
        if (groups && ev.model()) {
            const auto& vars = ev.model()->design().variables();
            const std::pair<ffd::VariableKind, const char*> kinds[] = {{ffd::VariableKind::Translate, "translations"},
                                                                      {ffd::VariableKind::SectionScale, "section scalings"},
                                                                      {ffd::VariableKind::Taper, "tapers"},
                                                                      {ffd::VariableKind::PointCoordinate, "point coordinates"}};
            for (const auto& group : kinds) {
                // (Not a structured binding: clang 14, the sanitizer build's compiler, cannot capture one.)
                const ffd::VariableKind kind = group.first;
                std::vector<double> z = signs([&](std::size_t i) { return vars[i].kind == kind; });
                if (std::any_of(z.begin(), z.end(), [](double x) { return x != 0; })) checks.push_back({group.second, z});
            }
        }
        if (groups || n == 0) checks.push_back({"alpha", {}});

        std::vector<double> steps;
        for (double eps = hi; eps >= lo * (1 - 1e-9); eps /= 10) steps.push_back(eps);
        std::ostringstream csv;
        csv.precision(17);
        csv << "check,eps,J_plus,J_minus,centred_difference,adjoint,relative_error\n";
        nlohmann::ordered_json rows = nlohmann::ordered_json::array();
        std::vector<std::string> names;
        std::vector<std::vector<std::pair<double, double>>> series;
        bool allOk = true;
        std::printf("%s = %.12g at the case's design; %zu variables\n\n", name.c_str(), grad.value, n);
        for (const Check& ck : checks) {
            double D = 0;
            if (ck.z.empty()) {
                D = grad.dalpha > 0 ? grad.dalpha : -grad.dalpha;  // z = sign(dJ/dalpha)
            } else {
                for (std::size_t i = 0; i < n; ++i) D += grad.dv[i] * ck.z[i];
            }
            const double sAlpha = grad.dalpha >= 0 ? 1.0 : -1.0;
            std::printf("%s: adjoint D_z J = %.12g\n%12s %22s %22s %12s\n", ck.label.c_str(), D, "eps", "centred difference",
                        "adjoint", "rel. error");
            double best = std::numeric_limits<double>::infinity();
            std::vector<std::pair<double, double>> line;
            for (double eps : steps) {
                double jp = 0, jm = 0;
                if (ck.z.empty()) {
                    // Alpha: the same case at alpha +- eps (degrees), each with its own evaluator.
                    for (int side = 0; side < 2; ++side) {
                        io::CaseFile ca = c;
                        ca.flow.freeStream.alphaDeg += (side == 0 ? 1 : -1) * sAlpha * eps;
                        study::CaseEvaluator ea(ca, geometry);
                        const study::Evaluation r = evaluateOrThrow(ea, v0, cmd, true, format("alpha %+.3e", (side == 0 ? 1 : -1) * eps));
                        (side == 0 ? jp : jm) = functionalOf(name, r.flow->forces);
                    }
                } else {
                    for (int side = 0; side < 2; ++side) {
                        std::vector<double> w = v0;
                        for (std::size_t i = 0; i < n; ++i) w[i] += (side == 0 ? eps : -eps) * ck.z[i];
                        const study::Evaluation r = evaluateOrThrow(ev, w, cmd, true, ck.label + format(" at eps %+.1e", side == 0 ? eps : -eps));
                        (side == 0 ? jp : jm) = functionalOf(name, r.flow->forces);
                    }
                }
                const double fd = (jp - jm) / (2 * eps);
                const double err = std::abs(fd - D) / std::max(std::abs(D), 1e-300);
                best = std::min(best, err);
                line.push_back({eps, err});
                std::printf("%12.1e %22.14g %22.14g %12.3e\n", eps, fd, D, err);
                std::fflush(stdout);
                csv << '"' << ck.label << "\"," << eps << "," << jp << "," << jm << "," << fd << "," << D << "," << err << "\n";
                rows.push_back({{"check", ck.label}, {"eps", eps}, {"centred_difference", fd}, {"adjoint", D}, {"relative_error", err}});
            }
            const bool ok = best <= tolerance;
            allOk = allOk && ok;
            std::printf("%s: best relative error %.3e (%s the tolerance %.1e)\n\n", ck.label.c_str(), best,
                        ok ? "within" : "NOT within", tolerance);
            names.push_back(ck.label);
            series.push_back(line);
        }
        if (!csvPath.empty()) {
            writeTextAtomically(csvPath, csv.str(), "CSV file");
            say(cmd, "wrote " + csvPath);
        }
        if (!plotPath.empty()) {
            std::vector<PlotSeries> lines;
            for (std::size_t k = 0; k < series.size(); ++k) lines.push_back({names[k], series[k]});
            PlotOptions po;
            po.title = "Gradient check: directional derivative, adjoint vs centred differences";
            po.xLabel = "step eps";
            po.yLabel = "|centred difference - adjoint| / |adjoint|";
            po.logX = po.logY = po.reverseX = true;
            po.referenceY = tolerance;
            po.referenceLabel = "tolerance";
            writeSvgPlot(plotPath, lines, po);
            say(cmd, "wrote " + plotPath);
        }
        if (json) {
            nlohmann::ordered_json j;
            j["functional"] = name;
            j["value"] = grad.value;
            j["tolerance"] = tolerance;
            j["passed"] = allOk;
            j["rows"] = rows;
            std::printf("%s\n", j.dump(2).c_str());
        }
        return allOk ? kOk : kFailed;
    });
}

int cmdGradient(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::printf("%s", kGradientHelp);
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json"}, {"--functionals", "--csv"}, pos, val, err)) return usageError("gradient", err, kGradientHelp);
    if (pos.size() != 1) return usageError("gradient", "expected exactly one CASE file", kGradientHelp);
    std::vector<std::string> names{"CL", "CD", "CL/CD"};
    if (val.count("--functionals")) {
        names = splitList(val["--functionals"]);
        if (names.empty()) return usageError("gradient", "--functionals needs at least one of CL, CD, CM, CY, CL/CD", kGradientHelp);
        try {
            for (const std::string& n : names) study::checkGradientFunctional(n);
        } catch (const CaseError& e) {
            return usageError("gradient", std::string("--functionals: ") + e.what(), kGradientHelp);
        }
    }
    return runGradient(pos[0], names, val.count("--csv") ? val["--csv"] : "", val.count("--json") > 0);
}

int cmdGradientCheck(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::printf("%s", kCheckHelp);
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json", "--groups"}, {"--functional", "--eps-range", "--tolerance", "--csv", "--plot"}, pos, val, err)) {
        return usageError("gradient-check", err, kCheckHelp);
    }
    if (pos.size() != 1) return usageError("gradient-check", "expected exactly one CASE file", kCheckHelp);
    const std::string name = val.count("--functional") ? val["--functional"] : "CL/CD";
    double hi = 1e-1, lo = 1e-8, tolerance = 1e-6;
    try {
        study::checkGradientFunctional(name);
        if (val.count("--eps-range")) {
            const std::string r = val["--eps-range"];
            const auto colon = r.find(':');
            if (colon == std::string::npos) throw CaseError("--eps-range: expected HI:LO, e.g. 1e-1:1e-8");
            std::size_t used = 0;
            hi = std::stod(r.substr(0, colon), &used);
            lo = std::stod(r.substr(colon + 1), &used);
        }
        if (val.count("--tolerance")) tolerance = std::stod(val["--tolerance"]);
    } catch (const std::exception& e) {
        return usageError("gradient-check", std::string("bad option value: ") + e.what(), kCheckHelp);
    }
    if (!(hi > 0) || !(lo > 0) || lo > hi || hi / lo > 1e20 || !(tolerance > 0)) {
        return usageError("gradient-check", "--eps-range needs 0 < LO <= HI (at most 20 decades) and --tolerance > 0", kCheckHelp);
    }
    return runGradientCheck(pos[0], name, hi, lo, val.count("--groups") > 0, tolerance, val.count("--csv") ? val["--csv"] : "",
                            val.count("--plot") ? val["--plot"] : "", val.count("--json") > 0);
}

}  // namespace aero::app
