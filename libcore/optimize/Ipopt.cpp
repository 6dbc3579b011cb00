// Ipopt (interior point, Debian's coinor-libipopt-dev with MUMPS) behind optimize::Optimizer:
// limited-memory quasi-Newton Hessian (the design problems give first derivatives only), the
// linear rows passed as linear constraints, a failed evaluation reported as an evaluation error
// (Ipopt then cuts its line-search step), and the common optimality measure as an extra stop test.
#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>
#include <cmath>
#include <limits>

#include "optimize/Optimizer.h"
#include "optimize/Tracker.h"

namespace aero::optimize {

namespace {

using Ipopt::Index;
using Ipopt::Number;

constexpr double kInfinity = 1e19;  // Ipopt's default nlp_lower/upper_bound_inf magnitude
constexpr int kMaxRestarts = 5;     // Ipopt runs started again after a gradient failed

double bound(double v) { return std::isinf(v) ? (v < 0 ? -kInfinity : kInfinity) : v; }

class Nlp : public Ipopt::TNLP {
public:
    Nlp(Tracker& t, std::vector<double> start) : t_(t), p_(t.problem()), start_(std::move(start)) {}

    bool get_nlp_info(Index& n, Index& m, Index& nnzJac, Index& nnzHess, IndexStyleEnum& style) override {
        n = p_.size();
        m = static_cast<Index>(p_.linear.size() + p_.nonlinear.size());
        nnzJac = 0;
        for (const LinearRow& r : p_.linear) nnzJac += static_cast<Index>(r.index.size());
        nnzJac += static_cast<Index>(p_.nonlinear.size()) * n;
        nnzHess = 0;
        style = C_STYLE;
        return true;
    }

    bool get_bounds_info(Index n, Number* xl, Number* xu, Index, Number* gl, Number* gu) override {
        for (Index i = 0; i < n; ++i) {
            xl[i] = bound(p_.lower[i]);
            xu[i] = bound(p_.upper[i]);
        }
        Index k = 0;
        for (const LinearRow& r : p_.linear) {
            gl[k] = bound(r.lower);
            gu[k++] = bound(r.upper);
        }
        for (const ConstraintSpec& c : p_.nonlinear) {
            gl[k] = bound(c.lower);
            gu[k++] = bound(c.upper);
        }
        return true;
    }

    bool get_constraints_linearity(Index m, LinearityType* types) override {
        for (Index k = 0; k < m; ++k) {
            types[k] = k < static_cast<Index>(p_.linear.size()) ? Ipopt::TNLP::LINEAR : Ipopt::TNLP::NON_LINEAR;
        }
        return true;
    }

    bool get_starting_point(Index n, bool initX, Number* x, bool initZ, Number*, Number*, Index, bool initLambda,
                            Number*) override {
        if (!initX || initZ || initLambda) return false;
        for (Index i = 0; i < n; ++i) x[i] = start_[i];
        return true;
    }

    bool eval_f(Index, const Number* x, bool, Number& f) override {
        const Values* v = t_.values(x);
        if (!v) return false;
        f = v->objective;
        return true;
    }

    bool eval_grad_f(Index n, const Number* x, bool, Number* g) override {
        const Gradients* d = t_.gradients(x);
        if (!d) return false;
        for (Index i = 0; i < n; ++i) g[i] = d->objective[i];
        return true;
    }

    bool eval_g(Index n, const Number* x, bool, Index, Number* g) override {
        Index k = 0;
        const std::vector<double> xv(x, x + n);
        for (const LinearRow& r : p_.linear) g[k++] = r.value(xv);
        if (p_.nonlinear.empty()) return true;
        const Values* v = t_.values(x);
        if (!v) return false;
        for (double c : v->constraints) g[k++] = c;
        return true;
    }

    bool eval_jac_g(Index n, const Number* x, bool, Index, Index, Index* rows, Index* cols, Number* values) override {
        Index e = 0;
        if (!values) {
            Index k = 0;
            for (const LinearRow& r : p_.linear) {
                for (int i : r.index) {
                    rows[e] = k;
                    cols[e++] = i;
                }
                ++k;
            }
            for (std::size_t c = 0; c < p_.nonlinear.size(); ++c, ++k) {
                for (Index i = 0; i < n; ++i) {
                    rows[e] = k;
                    cols[e++] = i;
                }
            }
            return true;
        }
        for (const LinearRow& r : p_.linear) {
            for (double a : r.coefficient) values[e++] = a;
        }
        if (p_.nonlinear.empty()) return true;
        const Gradients* d = t_.gradients(x);
        if (!d) return false;
        for (const auto& row : d->constraints) {
            for (Index i = 0; i < n; ++i) values[e++] = row[i];
        }
        return true;
    }

    bool intermediate_callback(Ipopt::AlgorithmMode mode, Index iter, Number, Number, Number, Number mu, Number, Number,
                               Number, Number, Index, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
        if (t_.stopped()) return false;
        if (mode != Ipopt::RegularMode || t_.lastGradientPoint().empty()) return true;  // restoration: not an iterate
        mu_ = mu;
        if (t_.iterate(iter, t_.lastGradientPoint().data())) {
            converged_ = true;
            return false;
        }
        return !t_.stopped();
    }

    void finalize_solution(Ipopt::SolverReturn status, Index, const Number*, const Number*, const Number*, Index,
                           const Number*, const Number*, Number, const Ipopt::IpoptData*,
                           Ipopt::IpoptCalculatedQuantities*) override {
        status_ = status;
    }

    bool converged() const { return converged_; }
    double mu() const { return mu_; }  // the barrier parameter at the last regular iterate (0: none)
    Ipopt::SolverReturn status() const { return status_; }

private:
    Tracker& t_;
    const Problem& p_;
    const std::vector<double> start_;
    bool converged_ = false;
    double mu_ = 0;
    Ipopt::SolverReturn status_ = Ipopt::UNASSIGNED;
};

class IpoptOptimizer final : public Optimizer {
public:
    std::string name() const override { return "ipopt"; }

    Result minimize(const Problem& p, const Settings& s) override {
        p.check();
        Tracker t(p, s);
        std::vector<double> start = p.start;
        double mu = 0;  // a restart's barrier parameter: where the last run had brought it
        for (int restarts = 0;; ++restarts) {
            Ipopt::SmartPtr<Nlp> nlp = new Nlp(t, start);
            Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
            Ipopt::OptionsList& o = *app->Options();
            o.SetStringValue("sb", "yes");  // no banner
            o.SetIntegerValue("print_level", 0);
            o.SetStringValue("hessian_approximation", "limited-memory");
            o.SetStringValue("mu_strategy", "adaptive");
            o.SetStringValue("nlp_scaling_method", "none");  // the caller scales its variables
            o.SetNumericValue("tol", s.optimalityTolerance);
            o.SetNumericValue("constr_viol_tol", s.feasibilityTolerance);
            o.SetNumericValue("dual_inf_tol", s.optimalityTolerance);
            o.SetIntegerValue("max_iter", std::max(1, s.maxIterations - t.iterations()));
            o.SetNumericValue("bound_relax_factor", 0.0);  // the bounds are the user's, exactly
            if (mu > 0) {
                // A restart goes on from an iterate: the barrier where it was, and the point not
                // pushed away from bounds it may lie close to (Ipopt's warm-start settings).
                o.SetNumericValue("mu_init", mu);
                o.SetNumericValue("bound_push", 1e-9);
                o.SetNumericValue("bound_frac", 1e-9);
            }
            if (app->Initialize() != Ipopt::Solve_Succeeded) return t.result(Status::Failed, "Ipopt could not start");
            const Ipopt::ApplicationReturnStatus r = app->OptimizeTNLP(nlp);
            if (nlp->converged() || r == Ipopt::Solve_Succeeded) {
                return t.result(Status::Converged, "optimality and feasibility within their tolerances");
            }
            if (t.stopped()) {
                return t.result(t.stopStatus(), t.stopStatus() == Status::Cancelled ? "cancelled" : "the evaluation limit was reached");
            }
            // Ipopt cannot cut a step whose values it has accepted: a gradient that fails there (a
            // converged flow whose adjoint does not converge, e.g. next to a turning point of the
            // steady states) ends its run. That point is made a failed evaluation and Ipopt starts
            // again from the last iterate, its quasi-Newton memory lost, so a step back to it is cut.
            const std::vector<double> failed = t.failedGradientPoint();
            const std::vector<double>& last = t.lastGradientPoint();
            if ((r == Ipopt::Invalid_Number_Detected || r == Ipopt::Error_In_Step_Computation) && !failed.empty() &&
                !last.empty() && last != failed && restarts < kMaxRestarts && t.iterations() < s.maxIterations) {
                const std::string why = "its gradient could not be computed (" + t.lastFailure() + ")";
                t.log("the gradient failed at a point Ipopt had accepted: " + t.lastFailure() + "; Ipopt starts again from iteration " +
                      std::to_string(t.iterations()) + "'s point, and that point counts as a failed evaluation");
                t.refuse(failed, why);
                t.restarted();
                start = last;
                if (nlp->mu() > 0) mu = nlp->mu();
                continue;
            }
            switch (r) {
                case Ipopt::Solved_To_Acceptable_Level:
                    return t.result(Status::Stalled, "Ipopt stopped at an acceptable point (its tolerances not reached)");
                case Ipopt::Maximum_Iterations_Exceeded:
                    return t.result(Status::IterationLimit, "the iteration limit was reached");
                case Ipopt::Infeasible_Problem_Detected:
                    return t.result(Status::Infeasible, "Ipopt converged to a point of locally minimal infeasibility");
                case Ipopt::Search_Direction_Becomes_Too_Small:
                    return t.result(Status::Stalled, "the search direction became too small");
                case Ipopt::Restoration_Failed:
                    return t.result(Status::Stalled, "Ipopt's feasibility restoration failed" +
                                                         (t.lastFailure().empty() ? std::string() : " (last failure: " + t.lastFailure() + ")"));
                case Ipopt::Invalid_Number_Detected:
                case Ipopt::Error_In_Step_Computation:
                    return t.result(Status::Failed, "Ipopt could not continue" +
                                                        (t.lastFailure().empty() ? std::string() : ": " + t.lastFailure()));
                default:
                    return t.result(Status::Failed, "Ipopt stopped with status " + std::to_string(static_cast<int>(r)) +
                                                        (t.lastFailure().empty() ? std::string() : " (last failure: " + t.lastFailure() + ")"));
            }
        }
    }
};

}  // namespace

std::unique_ptr<Optimizer> makeIpopt() { return std::make_unique<IpoptOptimizer>(); }

}  // namespace aero::optimize
