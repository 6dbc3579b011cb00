#include "io/Options.h"

#include <cmath>
#include <cstdio>

namespace aero::io {

namespace {

std::string number(double x) {
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    char b[32];
    std::snprintf(b, sizeof b, "%g", x);
    return b;
}


// Table entries, one line each: a real in a range, an integer in a range, a switch, a choice.
// `field` maps the struct to the member (S& -> T&); the getter reads through it on a copy.
template <class S, class F>
Option<S> real(const char* key, const char* unit, double lo, bool loClosed, double hi, bool hiClosed, F field,
               const char* description) {
    Option<S> o;
    o.spec = {key, description, unit, OptionKind::Number, lo, hi, loClosed, hiClosed, {}};
    o.get = [field](const S& c) {
        S copy = c;
        return OptionValue(static_cast<double>(field(copy)));
    };
    o.set = [field](S& c, const OptionValue& v) { field(c) = std::get<double>(v); };
    return o;
}

template <class S, class F>
Option<S> integer(const char* key, long lo, long hi, F field, const char* description) {
    Option<S> o;
    o.spec = {key, description, "", OptionKind::Integer, static_cast<double>(lo), static_cast<double>(hi), true, true, {}};
    o.get = [field](const S& c) {
        S copy = c;
        return OptionValue(static_cast<long>(field(copy)));
    };
    o.set = [field](S& c, const OptionValue& v) { field(c) = static_cast<int>(std::get<long>(v)); };
    return o;
}

template <class S, class F>
Option<S> boolean(const char* key, F field, const char* description) {
    Option<S> o;
    o.spec = {key, description, "", OptionKind::Boolean, 0, 0, true, true, {}};
    o.get = [field](const S& c) {
        S copy = c;
        return OptionValue(static_cast<bool>(field(copy)));
    };
    o.set = [field](S& c, const OptionValue& v) { field(c) = std::get<bool>(v); };
    return o;
}

template <class S, class F>
Option<S> choice(const char* key, std::vector<std::string> choices, F field, const char* description) {
    Option<S> o;
    o.spec = {key, description, "", OptionKind::Choice, 0, 0, true, true, std::move(choices)};
    o.get = [field](const S& c) {
        S copy = c;
        return OptionValue(std::string(field(copy)));
    };
    o.set = [field](S& c, const OptionValue& v) { field(c) = std::get<std::string>(v); };
    return o;
}

}  // namespace

std::string OptionSpec::range() const {
    switch (kind) {
        case OptionKind::Number:
        case OptionKind::Integer:
            return std::string(lowerClosed ? "[" : "(") + number(lower) + ", " + number(upper) + (upperClosed ? "]" : ")");
        case OptionKind::Boolean:
            return "true, false";
        case OptionKind::Choice: {
            std::string s;
            for (const auto& c : choices) s += (s.empty() ? "" : ", ") + c;
            return s;
        }
        case OptionKind::Point:
            return "[x, y, z]";
    }
    return "";
}

std::string OptionSpec::check(const OptionValue& v) const {
    if (kind == OptionKind::Number || kind == OptionKind::Integer) {
        const double x = kind == OptionKind::Number ? std::get<double>(v) : static_cast<double>(std::get<long>(v));
        const bool above = lowerClosed ? x >= lower : x > lower;
        const bool below = upperClosed ? x <= upper : x < upper;
        if (!(above && below)) {
            const std::string shown = kind == OptionKind::Number ? std::to_string(x) : std::to_string(std::get<long>(v));
            return "value " + shown + " outside " + range() + (unit.empty() ? "" : " " + unit);
        }
    } else if (kind == OptionKind::Choice) {
        const std::string& s = std::get<std::string>(v);
        for (const auto& c : choices) {
            if (c == s) return "";
        }
        return "unknown value '" + s + "' (expected " + range() + ")";
    }
    return "";
}

std::string formatOptionValue(const OptionValue& v) {
    if (const auto* d = std::get_if<double>(&v)) return number(*d);
    if (const auto* i = std::get_if<long>(&v)) return std::to_string(*i);
    if (const auto* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
    if (const auto* s = std::get_if<std::string>(&v)) return "\"" + *s + "\"";
    const auto& p = std::get<std::array<double, 3>>(v);
    return "[" + number(p[0]) + ", " + number(p[1]) + ", " + number(p[2]) + "]";
}

const std::vector<Option<FlowCase>>& flowOptions() {
    static const std::vector<Option<FlowCase>> options = [] {
        std::vector<Option<FlowCase>> o;
        o.push_back(real<FlowCase>("mach", "", 0, false, 10, false, [](FlowCase& c) -> double& { return c.freeStream.mach; },
                                   "free-stream Mach number"));
        o.push_back(real<FlowCase>("alpha", "degrees", -90, false, 90, false,
                                   [](FlowCase& c) -> double& { return c.freeStream.alphaDeg; },
                                   "angle of attack; the free stream is M (cos a, 0, sin a): X downstream, Z up, Y normal "
                                   "to the symmetry plane"));
        o.push_back(real<FlowCase>("gamma", "", 1, false, 3, false, [](FlowCase& c) -> double& { return c.freeStream.gamma; },
                                   "ratio of specific heats"));
        o.push_back(real<FlowCase>("reference_area", "length^2", 1e-12, true, 1e12, true,
                                   [](FlowCase& c) -> double& { return c.reference.area; },
                                   "S_ref of the coefficients (default: the half-sphere's half frontal disc, pi/2; the "
                                   "grid's half body when a symmetry plane halves it)"));
        o.push_back(real<FlowCase>("reference_length", "length", 1e-12, true, 1e12, true,
                                   [](FlowCase& c) -> double& { return c.reference.length; },
                                   "c_ref of the moment coefficient"));
        {
            Option<FlowCase> p;
            p.spec = {"reference_point", "moment reference point; CM is the moment about +Y", "length", OptionKind::Point,
                      0, 0, true, true, {}};
            p.get = [](const FlowCase& c) { return OptionValue(c.reference.point); };
            p.set = [](FlowCase& c, const OptionValue& v) { c.reference.point = std::get<std::array<double, 3>>(v); };
            o.push_back(std::move(p));
        }
        {
            Option<FlowCase> s;
            s.spec = {"scheme",
                      "interior inviscid discretization: the SBP operator in flux-difference form with an "
                      "entropy-conservative two-point flux (stable with little dissipation), or the classical "
                      "conservative central form (needs kappa4 0.05 on the half-sphere grids); docs/validation.md",
                      "", OptionKind::Choice, 0, 0, true, true, {"entropy_conservative", "central"}};
            s.get = [](const FlowCase& c) {
                return OptionValue(std::string(c.scheme == flow::InviscidScheme::Central ? "central" : "entropy_conservative"));
            };
            s.set = [](FlowCase& c, const OptionValue& v) {
                c.scheme = std::get<std::string>(v) == "central" ? flow::InviscidScheme::Central
                                                                  : flow::InviscidScheme::EntropyConservative;
            };
            o.push_back(std::move(s));
        }
        o.push_back(real<FlowCase>("kappa2", "", 0, true, 10, false, [](FlowCase& c) -> double& { return c.dissipation.kappa2; },
                                   "second-difference dissipation coefficient (shocks, scaled by the pressure switch)"));
        o.push_back(real<FlowCase>("kappa4", "", 0, true, 1, false, [](FlowCase& c) -> double& { return c.dissipation.kappa4; },
                                   "fourth-difference (background) dissipation coefficient"));
        o.push_back(real<FlowCase>("switch_smoothing", "", 0, true, 0.5, true,
                                   [](FlowCase& c) -> double& { return c.dissipation.switchSmoothing; },
                                   "width of the smooth maxima in the pressure switch (of the neighbours' switches, and in "
                                   "the fourth-difference coefficient; 0: the kinked JST form): Newton converges where the "
                                   "switch would flip between branches at a shock; the switch's absolute value stays exact, "
                                   "so the forces change little (docs/validation.md)"));
        o.push_back(boolean<FlowCase>("grid_aware_dissipation", [](FlowCase& c) -> bool& { return c.dissipation.gridAware; },
                            "the fourth difference scaled by the grid's own spacing ratio in each direction, so on a "
                            "stretched grid it does not act as a first-order wall friction; false: the index-space "
                            "operator"));
        o.push_back(real<FlowCase>("tolerance", "", 0, false, 1, false,
                                   [](FlowCase& c) -> double& { return c.newton.relativeTolerance; },
                                   "stop when the residual has fallen by this factor (relative to the free stream's "
                                   "residual on the grid, or to the first run's when restarted)"));
        o.push_back(integer<FlowCase>("max_iterations", 1, 100000, [](FlowCase& c) -> int& { return c.newton.maxIterations; },
                            "nonlinear iterations"));
        o.push_back(real<FlowCase>("max_seconds", "seconds", 0, true, 1e9, true,
                                   [](FlowCase& c) -> double& { return c.maxSeconds; },
                                   "wall time the flow stage may take with all its solves (grid sequencing, the retries "
                                   "from the free stream, the continuation in the dissipation); when it is spent the solve "
                                   "stops with status time-limit and no further retry or mode analysis starts (an "
                                   "optimizer counts the evaluation as failed; 0: no limit)"));
        o.push_back(real<FlowCase>("checkpoint_seconds", "seconds", 0, true, 1e9, true,
                                   [](FlowCase& c) -> double& { return c.checkpointSeconds; },
                                   "during a solve, `aeroform-cli flow` writes its restart file (output.restart, or "
                                   "CASE.restart next to the case) at most this often, so a killed run loses at most "
                                   "this much work and continues with --restart (0: after every iteration)"));
        o.push_back(integer<FlowCase>("stall_iterations", 2, 100000,
                                      [](FlowCase& c) -> int& { return c.newton.stallIterations; },
                                      "stop as stalled after this many iterations without a new best residual or a new highest CFL "
                                      "below stall_cfl_ceiling"));
        o.push_back(real<FlowCase>("stall_cfl_ceiling", "", 1, true, 1e12, true,
                                   [](FlowCase& c) -> double& { return c.newton.stallCflCeiling; },
                                   "a new highest CFL counts as progress against stall_iterations only below this (above "
                                   "it the steps are Newton's: a CFL still growing there is no transient)"));
        o.push_back(integer<FlowCase>("exact_recovery_iterations", 0, 100000,
                                      [](FlowCase& c) -> int& { return c.newton.recoveryIterations; },
                                      "after a Newton step's linear solve fails, the Newton steps that follow have this many "
                                      "iterations to reach a new best residual; if they do not, approximate-Newton steps take "
                                      "over until they crawl (0: never)"));
        o.push_back(real<FlowCase>("switch_continuation", "", 0, true, 0.5, true,
                                   [](FlowCase& c) -> double& { return c.newton.switchContinuation; },
                                   "a solve that starts above switch_continuation_until first solves with the pressure "
                                   "switch smoothed to this width (a differentiable residual: Newton converges where the "
                                   "kinked switch makes the iteration wander), then continues with the case's own switch "
                                   "(switch_smoothing) from that state, also when the smoothed solve stalls or keeps "
                                   "rejecting steps; the answer is always the case's own residual's (0: off)"));
        o.push_back(real<FlowCase>("switch_continuation_until", "", 1e-14, true, 1, false,
                                   [](FlowCase& c) -> double& { return c.newton.switchContinuationUntil; },
                                   "relative residual at which the smoothed switch hands over to the case's own "
                                   "(earlier if the smoothed solve stalls)"));
        o.push_back(real<FlowCase>("cfl0", "", 0, false, 1e12, false, [](FlowCase& c) -> double& { return c.newton.cfl0; },
                                   "initial CFL number (the CFL also grows as R0/R)"));
        o.push_back(real<FlowCase>("cfl_growth", "", 1, true, 100, false,
                                   [](FlowCase& c) -> double& { return c.newton.cflGrowth; },
                                   "growth of the CFL base per full step"));
        o.push_back(real<FlowCase>("cfl_max", "", 0, false, 1e12, true,
                                   [](FlowCase& c) -> double& { return c.newton.cflMax; },
                                   "the CFL at most (pseudo-time steps stay this short: a ceiling where the exact Newton "
                                   "systems of larger CFLs defeat GMRES; 1e12: Newton)"));
        o.push_back(real<FlowCase>("linear_tolerance", "", 0, false, 1, false,
                                   [](FlowCase& c) -> double& { return c.newton.linearTolerance; },
                                   "GMRES relative tolerance per nonlinear iteration"));
        o.push_back(real<FlowCase>("final_forcing", "", 0, true, 0.5, true,
                                   [](FlowCase& c) -> double& { return c.newton.finalForcing; },
                                   "the last Newton step's GMRES tolerance at most: when linear_tolerance would take "
                                   "the residual past the tolerance by more than needed (and the step before reduced "
                                   "it by more than the factor left), GMRES solves to half that factor, up to this "
                                   "value (0: always linear_tolerance)"));
        o.push_back(integer<FlowCase>("ilu_fill", 0, 4, [](FlowCase& c) -> int& { return c.newton.iluFill; },
                            "level of fill of the block ILU preconditioner"));
        o.push_back(integer<FlowCase>("ilu_parts", 1, 64, [](FlowCase& c) -> int& { return c.newton.preconditionerParts; },
                            "the ILU is factored and applied in this many groups of mesh blocks in parallel, their "
                            "coupling kept through a separator ordered last (1 = natural order, sequential); fixed per "
                            "case rather than taken from the thread count, so a run takes the same iterations on any "
                            "machine"));
        {
            Option<FlowCase> s;
            s.spec = {"jacobian_products",
                      "how the Newton steps' GMRES forms Jacobian-vector products: the difference of two real "
                      "residuals (about 3.5 times cheaper) or complex step (exact to round-off)",
                      "", OptionKind::Choice, 0, 0, true, true, {"difference", "complex_step"}};
            s.get = [](const FlowCase& c) {
                return OptionValue(std::string(c.newton.products == flow::ProductMode::ComplexStep ? "complex_step"
                                                                                                   : "difference"));
            };
            s.set = [](FlowCase& c, const OptionValue& v) {
                c.newton.products = std::get<std::string>(v) == "complex_step" ? flow::ProductMode::ComplexStep
                                                                               : flow::ProductMode::Difference;
            };
            o.push_back(std::move(s));
        }
        o.push_back(integer<FlowCase>("gmres_restart", 5, 500, [](FlowCase& c) -> int& { return c.newton.gmresRestart; },
                            "Krylov vectors per GMRES cycle of a Newton step (memory: 5 values per grid node each)"));
        o.push_back(integer<FlowCase>("gmres_max_iterations", 1, 100000,
                                      [](FlowCase& c) -> int& { return c.newton.gmresMaxIterations; },
                                      "GMRES iterations at most per Newton step (over its restart cycles)"));
        o.push_back(integer<FlowCase>("gmres_deflation", 0, 200, [](FlowCase& c) -> int& { return c.newton.gmresDeflation; },
                            "harmonic Ritz vectors a Newton step's GMRES keeps over a restart (GMRES-DR; 0: plain "
                            "restarts); below gmres_restart - 1"));
        o.push_back(boolean<FlowCase>("gmres_single_basis", [](FlowCase& c) -> bool& { return c.newton.gmresSingleBasis; },
                            "store a Newton step's Krylov basis in single precision (half its memory: 5 x 4 bytes per "
                            "grid node and vector; products, sums and restarts stay double): for grids where memory "
                            "is the limit"));
        o.push_back(real<FlowCase>("gmres_reorthogonalize_below", "", 0, true, 1, true,
                                   [](FlowCase& c) -> double& { return c.newton.gmresReorthogonalizeBelow; },
                                   "a Newton step's GMRES repeats its Gram-Schmidt pass where the first left the new "
                                   "vector shorter than this fraction of its length (0.71: the DGKS test of the adjoint; "
                                   "0: one pass always; 1: two always); 0.1 takes the same iterations on the 75k and 98k "
                                   "samples with 0.6 times the sweeps over the basis"));
        {
            Option<FlowCase> s;
            s.spec = {"ilu_precision",
                      "storage of the preconditioner's ILU factors (computed in double, stored rounded): bfloat16 "
                      "halves their memory against single (0.75 GB on the 903k paper grid) with the same "
                      "iterations on the samples: for grids where memory is the limit; docs/performance.md",
                      "", OptionKind::Choice, 0, 0, true, true, {"single", "bfloat16", "double"}};
            s.get = [](const FlowCase& c) {
                const flow::IluPrecision p = c.newton.iluPrecision;
                return OptionValue(std::string(p == flow::IluPrecision::Double     ? "double"
                                               : p == flow::IluPrecision::Bfloat16 ? "bfloat16"
                                                                                   : "single"));
            };
            s.set = [](FlowCase& c, const OptionValue& v) {
                const std::string& p = std::get<std::string>(v);
                c.newton.iluPrecision = p == "double"     ? flow::IluPrecision::Double
                                        : p == "bfloat16" ? flow::IluPrecision::Bfloat16
                                                          : flow::IluPrecision::Single;
            };
            o.push_back(std::move(s));
        }
        o.push_back(integer<FlowCase>("low_memory_nodes", 0, 2000000000,
                                      [](FlowCase& c) -> int& { return c.newton.lowMemoryNodes; },
                                      "from this many grid nodes on, the approximate Jacobian is kept after its ILU is "
                                      "factored only in float and only for approximate steps, and the Krylov basis is "
                                      "freed between steps, so the two are never held at full size together; and the ILU "
                                      "factors are stored in bfloat16 and the basis in float, whatever ilu_precision and "
                                      "gmres_single_basis say (the 903k paper grid: 3.59 GB instead of 6.32 GB; the 75k "
                                      "half-sphere 273 MB instead of 479 MB) (0: always)"));
        o.push_back(real<FlowCase>("lumping", "", 0, false, 1000, false,
                                   [](FlowCase& c) -> double& { return c.dissipation.lumping; },
                                   "sigma of the preconditioner's lumped dissipation (fourth-difference coefficient moved "
                                   "to the second difference); smaller is closer to the real operator but less "
                                   "diagonally dominant"));
        o.push_back(real<FlowCase>("exact_lumping", "", 0, true, 1000, false,
                                   [](FlowCase& c) -> double& { return c.newton.exactLumping; },
                                   "the lumping factor of the Newton steps' preconditioner from CFL 1e6 on, when it is "
                                   "below `lumping` and GMRES has not had to raise that: a preconditioner nearer the "
                                   "exact Jacobian for the last orders; it changes which hard flows converge faster rather "
                                   "than the average (docs/performance.md) (0: `lumping` throughout)"));
        o.push_back(boolean<FlowCase>("local_cfl", [](FlowCase& c) -> bool& { return c.newton.localCfl; },
                            "per-node CFL factors: a node the step would change by more than 30 % (density or "
                            "pressure) gets a smaller time step of its own instead of cutting the whole step, so "
                            "one node at a sharp edge does not hold the field's CFL down"));
        o.push_back(boolean<FlowCase>("grid_sequencing", [](FlowCase& c) -> bool& { return c.gridSequencing; },
                            "a cold start on a grid of sequencing_nodes nodes or more first converges on coarser "
                            "samplings of the same analytic grid (half the intervals, and a quarter while that "
                            "level still has sequencing_nodes nodes, ...; exact prolongation in the grid "
                            "parameters), then on the case's grid; one that fails there is solved again from the "
                            "free stream"));
        o.push_back(integer<FlowCase>("sequencing_nodes", 0, 2000000000,
                                      [](FlowCase& c) -> int& { return c.sequencingNodes; },
                                      "grid sequencing starts from this many grid nodes on, and a coarser level is "
                                      "added while the coarsest level has this many (the 75k half-sphere: one level "
                                      "of 11k nodes; the 903k paper grid: 123k and 21k)"));
        o.push_back(boolean<FlowCase>("stall_modes", [](FlowCase& c) -> bool& { return c.stallModes; },
                            "a solve that does not converge looks for the linear modes of the flow that grow in "
                            "pseudo time at its final state (Arnoldi on one implicit step at CFL 50: about 30 GMRES "
                            "solves) and names the fastest, where it is and what to do in its reason; none growing "
                            "means a steady state the solver's path missed"));
        return o;
    }();
    return options;
}

const std::vector<Option<OptimizationCase>>& optimizationOptions() {
    using O = OptimizationCase;
    static const std::vector<Option<O>> options = [] {
        std::vector<Option<O>> o;
        o.push_back(choice<O>("objective", {"CL/CD", "CL", "CD", "CM", "CY", "pressure"},
                              [](O& c) -> std::string& { return c.objective; },
                              "the functional optimized (its exact gradient by the discrete adjoint); pressure: the "
                              "inverse design's 1/2 sum (p - p_target)^2 dA over the wall, against target_pressure"));
        {
            Option<O> s;
            s.spec = {"sense", "maximize or minimize the objective", "", OptionKind::Choice, 0, 0, true, true,
                      {"maximize", "minimize"}};
            s.get = [](const O& c) { return OptionValue(std::string(c.maximize ? "maximize" : "minimize")); };
            s.set = [](O& c, const OptionValue& v) { c.maximize = std::get<std::string>(v) == "maximize"; };
            o.push_back(std::move(s));
        }
        o.push_back(real<O>("objective_scale", "", 0, false, 1e12, false, [](O& c) -> double& { return c.objectiveScale; },
                            "the optimizer sees this times the objective (a gradient of order one helps its first "
                            "step)"));
        {
            Option<O> s;
            s.spec = {"variable_scaling",
                      "none: the optimizer's variables are the design variables in the case's units (lengths, "
                      "factors) and alpha in degrees; range: each divided by its range (upper - lower bound), "
                      "which makes a quasi-Newton first step larger on wide ranges",
                      "", OptionKind::Choice, 0, 0, true, true, {"none", "range"}};
            s.get = [](const O& c) { return OptionValue(std::string(c.rangeScaling ? "range" : "none")); };
            s.set = [](O& c, const OptionValue& v) { c.rangeScaling = std::get<std::string>(v) == "range"; };
            o.push_back(std::move(s));
        }
        o.push_back(choice<O>("optimizer", {"ipopt", "slsqp"}, [](O& c) -> std::string& { return c.optimizer; },
                              "Ipopt (interior point, limited-memory Hessian) or NLopt's SLSQP; both stop on the same "
                              "first-order optimality measure"));
        o.push_back(real<O>("optimality_tolerance", "", 0, false, 1, false,
                            [](O& c) -> double& { return c.optimalityTolerance; },
                            "stop when the Lagrangian's gradient (in the scaled variables) is below this"));
        o.push_back(real<O>("feasibility_tolerance", "", 0, false, 1, false,
                            [](O& c) -> double& { return c.feasibilityTolerance; },
                            "largest constraint violation of a converged design"));
        o.push_back(integer<O>("max_iterations", 1, 10000, [](O& c) -> int& { return c.maxIterations; },
                               "major iterations of the optimizer"));
        o.push_back(integer<O>("max_evaluations", 1, 100000, [](O& c) -> int& { return c.maxEvaluations; },
                               "function evaluations (flow solves), failed ones included"));
        o.push_back(boolean<O>("alpha_variable", [](O& c) -> bool& { return c.alphaVariable; },
                               "the angle of attack is a design variable too, starting from flow.alpha"));
        o.push_back(real<O>("alpha_lower", "degrees", -90, false, 90, false, [](O& c) -> double& { return c.alphaLower; },
                            "lower bound of the angle of attack when it is a variable"));
        o.push_back(real<O>("alpha_upper", "degrees", -90, false, 90, false, [](O& c) -> double& { return c.alphaUpper; },
                            "upper bound of the angle of attack when it is a variable"));
        o.push_back(real<O>("min_corner_ratio", "", 0, true, 1, false, [](O& c) -> double& { return c.minCornerRatio; },
                            "grid validity: a smooth minimum (Kreisselmeier-Steinhauser, rho 50) over every grid cell "
                            "corner of log(Jacobian / baseline Jacobian) is kept above log(this), with its exact "
                            "gradient through the mesh adjoint, so the optimizer turns away before the moved grid "
                            "folds; 0: no such constraint"));
        o.push_back(real<O>("max_wall_bend", "degrees", 0, true, 180, false, [](O& c) -> double& { return c.maxWallBend; },
                            "shape resolution: a smooth maximum (Kreisselmeier-Steinhauser over 1 - cos, rho 1000) of "
                            "the angle the wall turns from one grid node to the next is kept below this, with its exact "
                            "gradient, so the optimizer does not fold the wall into bends the grid cannot resolve (the "
                            "flow there is not resolved and tends to stall; docs/validation.md); 0: no such constraint"));
        o.push_back(real<O>("max_wall_mach", "", 0, true, 10, false, [](O& c) -> double& { return c.maxWallMach; },
                            "flow regime: a smooth maximum (Kreisselmeier-Steinhauser, rho 50) of the local Mach number "
                            "at the wall nodes is kept below this, with its exact gradient (a flow adjoint of its own "
                            "per gradient), so the optimizer does not climb by growing supersonic pockets and shocks, "
                            "whose Euler flows stop converging on finer grids (docs/validation.md); near the bound the "
                            "aggregate is above the largest wall Mach number by up to about 0.05 (more below it); 0: no "
                            "such constraint"));
        o.push_back(real<O>("max_entropy", "", 0, true, 100, false, [](O& c) -> double& { return c.maxEntropy; },
                            "flow credibility: an evaluation whose flow converges with a largest entropy error "
                            "|s - s_inf| above this is reported to the optimizer as failed (status flow-unresolved), "
                            "so the step is cut: a smooth body at subsonic free-stream Mach generates entropy only "
                            "where the grid does not resolve the flow or the solution separated (a steady state the "
                            "continuation in the dissipation can land on); its state is not used for warm starts; 0: "
                            "any converged flow counts"));
        o.push_back(real<O>("max_entropy_rise", "", 0, true, 1e6, false,
                            [](O& c) -> double& { return c.maxEntropyRise; },
                            "flow continuity along the path: an evaluation whose flow converges with a largest "
                            "entropy error more than this many times that of the design it started from (the "
                            "closer of the optimizer's last two iterates) is reported to "
                            "the optimizer as failed (status flow-unresolved), so the step is cut: a step between "
                            "nearby designs changes a flow continuously, and a jump by such a factor is a switch to "
                            "another steady state (typically a separated one), not the next point of the path; "
                            "unlike max_entropy it lets the entropy grow gradually, as it does on coarse grids "
                            "(docs/validation.md); 0: any rise"));
        o.push_back(choice<O>("warm_start_fallback", {"continuation", "free_stream", "none"},
                              [](O& c) -> std::string& { return c.warmStartFallback; },
                              "what an evaluation does when its warm start from the design its step came from stalls "
                              "or diverges: continuation solves again from the free stream and then by "
                              "continuation in the dissipation (the most robust, and slow: on the 98k "
                              "sphere-to-BWB path 400-1,100 s per evaluation, ending on separated states); "
                              "free_stream solves again from the free stream only; none makes it a failed "
                              "evaluation at once, so the optimizer cuts the step (a stalled warm start from a "
                              "nearby converged design usually means the step went too far). An evaluation "
                              "without a warm start (the first) always takes the whole ladder"));
        o.push_back(integer<O>("warm_start_iterations", 0, 100000, [](O& c) -> int& { return c.warmStartIterations; },
                               "a step from an accepted design whose warm start has not converged after this many flow "
                               "iterations fails as a stalled one does (then warm_start_fallback applies): a warm "
                               "start from a converged neighbour converges in 5-40 iterations on the 98k path, and "
                               "one that needs more crawls towards a nearly singular state (2 % per iteration) for "
                               "up to flow.max_iterations; one whose last ten iterations' rate reaches the tolerance "
                               "within 30 more gets those and two (more where steps were rejected), and so again while "
                               "that holds (three times at most); 0: flow.max_iterations"));
        o.push_back(boolean<O>("stall_modes", [](O& c) -> bool& { return c.stallModes; },
                               "a step from an accepted design whose flow does not converge also looks for the "
                               "flow's growing modes (flow.stall_modes: about a minute at 98k nodes, more than an "
                               "accepted evaluation and its gradient take); off, the step is cut with the stall's "
                               "place and local Mach number, and aeroform-cli optimize --design N writes the "
                               "design as a case for aeroform-cli flow to analyse. The first evaluation follows "
                               "flow.stall_modes"));
        o.push_back(boolean<O>("lift_constraint", [](O& c) -> bool& { return c.liftConstraint; },
                               "keep CL equal to target_cl (with its exact gradient)"));
        o.push_back(real<O>("target_cl", "", -100, true, 100, true, [](O& c) -> double& { return c.targetCL; },
                            "the lift coefficient kept when lift_constraint is true"));
        return o;
    }();
    return options;
}

const std::vector<Option<MeshCase>>& meshOptions() {
    static const std::vector<Option<MeshCase>> options = [] {
        std::vector<Option<MeshCase>> o;
        {
            // First in the table: the parser applies the level before the keys that override it.
            Option<MeshCase> l;
            l.spec = {"level",
                      "the named grid level; the keys below override its values. coarse: 98,260 nodes on the "
                      "half-sphere, wall spacing 1e-2 (the optimization grid); medium: 306,820, wall spacing 1e-3; "
                      "paper: 903,340 (13,546 control nodes), wall spacing 1e-3 as the paper. No level has a spacing "
                      "jump between the wall layer and the radial distribution",
                      "", OptionKind::Choice, 0, 0, true, true, {"coarse", "medium", "paper"}};
            l.get = [](const MeshCase& m) { return OptionValue(m.level); };
            l.set = [](MeshCase& m, const OptionValue& v) {
                m.level = std::get<std::string>(v);
                m.extrusion = mesh::extrusionLevel(m.level);
            };
            o.push_back(std::move(l));
        }
        o.push_back(real<MeshCase>("farfield_radius", "body radii", 1, false, 1e6, false,
                                   [](MeshCase& m) -> double& { return m.extrusion.farfieldRadius; },
                                   "farfield sphere radius"));
        o.push_back(integer<MeshCase>("radial_control_points", 4, 1000,
                                      [](MeshCase& m) -> int& { return m.extrusion.radialControlPoints; },
                                      "control nodes per wall-to-farfield column (medium 18, paper 26)"));
        o.push_back(real<MeshCase>("control_wall_spacing", "body radii", 0, false, 1, false,
                                   [](MeshCase& m) -> double& { return m.extrusion.controlWallSpacing; },
                                   "first control layer off the wall"));
        o.push_back(integer<MeshCase>("surface_nodes", 2, 10000, [](MeshCase& m) -> int& { return m.extrusion.surfaceNodes; },
                                      "grid nodes per block edge along the wall (medium 23, paper 31)"));
        o.push_back(integer<MeshCase>("radial_nodes", 2, 10000, [](MeshCase& m) -> int& { return m.extrusion.radialNodes; },
                                      "grid nodes wall to farfield; the spacing grows smoothly in physical space from "
                                      "grid_wall_spacing to the farfield (medium 29, paper 47)"));
        o.push_back(real<MeshCase>("grid_wall_spacing", "body radii", 0, false, 1, false,
                                   [](MeshCase& m) -> double& { return m.extrusion.gridWallSpacing; },
                                   "first grid spacing off the wall (medium and paper 1e-3)"));
        o.push_back(real<MeshCase>("refine", "", 0, false, 100, false, [](MeshCase& m) -> double& { return m.extrusion.refine; },
                                   "multiplies the grid intervals: the same analytic grid, finer"));
        o.push_back(integer<MeshCase>("increments", 1, 1000, [](MeshCase& m) -> int& { return m.elasticity.increments; },
                                      "m of Eq. 7: the elasticity move in this many steps (more survive larger "
                                      "deformations)"));
        o.push_back(real<MeshCase>("poisson", "", -1, false, 0.5, false,
                                   [](MeshCase& m) -> double& { return m.elasticity.poisson; },
                                   "Poisson's ratio of the pseudo-solid (the paper's negative value)"));
        o.push_back(real<MeshCase>("size_stiffening", "", -10, true, 10, true,
                                   [](MeshCase& m) -> double& { return m.elasticity.sizeStiffening; },
                                   "Young's modulus ~ (mean volume / cell volume)^value: small cells stiffer"));
        o.push_back(real<MeshCase>("orthogonality_stiffening", "", 0, true, 100, true,
                                   [](MeshCase& m) -> double& { return m.elasticity.orthogonalityStiffening; },
                                   "Young's modulus *= 1 + value (1 - min scaled Jacobian): skewed cells stiffer"));
        o.push_back(real<MeshCase>("tolerance", "", 0, false, 1, false,
                                   [](MeshCase& m) -> double& { return m.elasticity.tolerance; },
                                   "relative residual of each increment's PCG solve"));
        return o;
    }();
    return options;
}

}  // namespace aero::io
