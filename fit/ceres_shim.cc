// The C interface of fit/ceres_shim.h over Ceres Solver 2.x.
#include "fit/ceres_shim.h"

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

namespace {

// One residual block whose values and Jacobians come from a C callback.
class CallbackCost final : public ceres::CostFunction {
 public:
  CallbackCost(sf_lsq_residual_fn fn, void *user, int n_residuals, const std::vector<int> &sizes)
      : fn_(fn), user_(user) {
    set_num_residuals(n_residuals);
    for (int s : sizes) mutable_parameter_block_sizes()->push_back(s);
  }
  bool Evaluate(double const *const *parameters, double *residuals,
                double **jacobians) const override {
    return fn_(user_, parameters, residuals, jacobians) != 0;
  }

 private:
  sf_lsq_residual_fn fn_;
  void *user_;
};

// A tall residual block handed to Ceres as the p + 1 rows of the Cholesky
// factor of its Gram matrix (fit/ceres_shim.h, sf_lsq_add_gram_residuals).
class GramCost final : public ceres::CostFunction {
 public:
  GramCost(sf_lsq_gram_fn fn, void *user, const std::vector<int> &sizes)
      : fn_(fn), user_(user) {
    int p = 0;
    for (int s : sizes) {
      mutable_parameter_block_sizes()->push_back(s);
      p += s;
    }
    set_num_residuals(p + 1);
    gram_.resize((size_t)(p + 1) * (p + 1));
    factor_.resize(gram_.size());
  }
  bool Evaluate(double const *const *parameters, double *residuals,
                double **jacobians) const override {
    const int m = num_residuals(), p = m - 1;
    bool want_jacobian = false;
    if (jacobians)
      for (size_t b = 0; b < parameter_block_sizes().size(); ++b)
        if (jacobians[b]) want_jacobian = true;
    double sum_squares = 0.0;
    if (!fn_(user_, parameters, &sum_squares, want_jacobian ? gram_.data() : nullptr) ||
        !std::isfinite(sum_squares))
      return false;
    if (!want_jacobian) {
      // Only |r'| = |r| matters where Ceres asks for residuals alone.
      residuals[0] = std::sqrt(sum_squares);
      for (int k = 1; k < m; ++k) residuals[k] = 0.0;
      return true;
    }
    if (!CholeskyUpper(m, sum_squares)) return false;
    for (int k = 0; k < m; ++k) residuals[k] = factor_[(size_t)k * m + p];
    int offset = 0;
    for (size_t b = 0; b < parameter_block_sizes().size(); ++b) {
      const int size = parameter_block_sizes()[b];
      if (jacobians[b])
        for (int k = 0; k < m; ++k)
          for (int j = 0; j < size; ++j)
            jacobians[b][(size_t)k * size + j] = factor_[(size_t)k * m + offset + j];
      offset += size;
    }
    return true;
  }

 private:
  // R (row-major, upper) with R^T R = gram_. A column whose pivot is lost to
  // rounding (a linear combination of the earlier ones) gets a zero row: its
  // remaining pivot is a difference of numbers that agree to ~eps, so
  // dividing by its root would turn rounding into large entries. The last
  // pivot is |r|^2 - |r'_{0..p-1}|^2, the part of r outside J's span,
  // clamped at 0, so that |r'|^2 = |r|^2.
  bool CholeskyUpper(int m, double sum_squares) const {
    const double *g = gram_.data();
    double *R = factor_.data();
    for (int k = 0; k < m; ++k) {
      const double diagonal = k + 1 == m ? sum_squares : g[(size_t)k * m + k];
      double d = diagonal;
      for (int i = 0; i < k; ++i) d -= R[(size_t)i * m + k] * R[(size_t)i * m + k];
      if (!std::isfinite(d)) return false;
      const bool lost = k + 1 == m ? d <= 0.0 : d <= kLostPivot * diagonal;
      for (int j = 0; j < m; ++j) R[(size_t)k * m + j] = 0.0;
      if (lost) continue;
      const double root = std::sqrt(d);
      R[(size_t)k * m + k] = root;
      for (int j = k + 1; j < m; ++j) {
        double e = g[(size_t)k * m + j];
        for (int i = 0; i < k; ++i) e -= R[(size_t)i * m + k] * R[(size_t)i * m + j];
        R[(size_t)k * m + j] = e / root;
      }
    }
    return true;
  }

  // 64 ulp of the column's squared norm: below this a pivot is rounding.
  static constexpr double kLostPivot = 64.0 * 2.220446049250313e-16;
  sf_lsq_gram_fn fn_;
  void *user_;
  mutable std::vector<double> gram_, factor_;
};

ceres::LossFunction *make_loss(sf_lsq_loss kind, double a) {
  switch (kind) {
    case SF_LSQ_LOSS_HUBER: return new ceres::HuberLoss(a);
    case SF_LSQ_LOSS_SOFT_L1: return new ceres::SoftLOneLoss(a);
    case SF_LSQ_LOSS_CAUCHY: return new ceres::CauchyLoss(a);
    default: return nullptr;
  }
}

}  // namespace

struct sf_lsq_problem {
  ceres::Problem problem;
  std::vector<double *> blocks;
  std::vector<int> sizes;
  int n_residuals = 0;
};

// The sizes and value arrays of the parameter blocks a residual block
// depends on; false for an index that names no block.
static bool blocks_of_residual(const sf_lsq_problem *p, int n_blocks, const int *blocks,
                               std::vector<int> *sizes, std::vector<double *> *values) {
  for (int b = 0; b < n_blocks; ++b) {
    if (blocks[b] < 0 || blocks[b] >= (int)p->blocks.size()) return false;
    sizes->push_back(p->sizes[blocks[b]]);
    values->push_back(p->blocks[blocks[b]]);
  }
  return true;
}

extern "C" {

void sf_lsq_options_default(sf_lsq_options *o) {
  o->max_iterations = 200;
  o->function_tolerance = 1e-12;
  o->gradient_tolerance = 1e-14;
  o->parameter_tolerance = 1e-12;
  o->n_threads = 1;
  o->normal_equations = 0;
  o->initial_trust_region_radius = 1e4;
  o->dogleg = 0;
  o->nonmonotonic_steps = 0;
  o->jacobi_scaling = 1;
}

const char *sf_lsq_termination_name(sf_lsq_termination t) {
  switch (t) {
    case SF_LSQ_CONVERGENCE: return "convergence";
    case SF_LSQ_NO_CONVERGENCE: return "no_convergence";
    default: return "failure";
  }
}

sf_lsq_problem *sf_lsq_problem_new(void) { return new (std::nothrow) sf_lsq_problem(); }

void sf_lsq_problem_free(sf_lsq_problem *p) { delete p; }

int sf_lsq_add_block(sf_lsq_problem *p, double *values, int size) {
  if (!p || !values || size <= 0) return -1;
  p->problem.AddParameterBlock(values, size);
  p->blocks.push_back(values);
  p->sizes.push_back(size);
  return (int)p->blocks.size() - 1;
}

int sf_lsq_set_bounds(sf_lsq_problem *p, int block, int index, double lower, double upper) {
  if (!p || block < 0 || block >= (int)p->blocks.size() || index < 0 || index >= p->sizes[block])
    return -1;
  if (std::isnan(lower) || std::isnan(upper) || lower > upper) return -1;
  if (std::isfinite(lower)) p->problem.SetParameterLowerBound(p->blocks[block], index, lower);
  if (std::isfinite(upper)) p->problem.SetParameterUpperBound(p->blocks[block], index, upper);
  return 0;
}

int sf_lsq_set_constant(sf_lsq_problem *p, int block) {
  if (!p || block < 0 || block >= (int)p->blocks.size()) return -1;
  p->problem.SetParameterBlockConstant(p->blocks[block]);
  return 0;
}

int sf_lsq_add_residuals(sf_lsq_problem *p, sf_lsq_residual_fn fn, void *user, int n_residuals,
                         int n_blocks, const int *blocks, sf_lsq_loss loss, double loss_scale) {
  if (!p || !fn || n_residuals <= 0 || n_blocks <= 0 || !blocks) return -1;
  if (loss != SF_LSQ_LOSS_NONE && !(loss_scale > 0.0 && std::isfinite(loss_scale))) return -1;
  std::vector<int> sizes;
  std::vector<double *> values;
  if (!blocks_of_residual(p, n_blocks, blocks, &sizes, &values)) return -1;
  p->problem.AddResidualBlock(new CallbackCost(fn, user, n_residuals, sizes),
                              make_loss(loss, loss_scale), values);
  p->n_residuals += n_residuals;
  return 0;
}

int sf_lsq_add_gram_residuals(sf_lsq_problem *p, sf_lsq_gram_fn fn, void *user, int n_blocks,
                              const int *blocks) {
  if (!p || !fn || n_blocks <= 0 || !blocks) return -1;
  std::vector<int> sizes;
  std::vector<double *> values;
  if (!blocks_of_residual(p, n_blocks, blocks, &sizes, &values)) return -1;
  auto *cost = new (std::nothrow) GramCost(fn, user, sizes);
  if (!cost) return -1;
  p->problem.AddResidualBlock(cost, nullptr, values);
  p->n_residuals += cost->num_residuals();
  return 0;
}

int sf_lsq_solve(sf_lsq_problem *p, const sf_lsq_options *o, sf_lsq_summary *s) {
  std::memset(s, 0, sizeof *s);
  sf_lsq_options defaults;
  sf_lsq_options_default(&defaults);
  if (!o) o = &defaults;
  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = o->dogleg ? ceres::DOGLEG : ceres::LEVENBERG_MARQUARDT;
  if (o->initial_trust_region_radius > 0.0) {
    options.initial_trust_region_radius = o->initial_trust_region_radius;
    if (options.max_trust_region_radius < o->initial_trust_region_radius)
      options.max_trust_region_radius = o->initial_trust_region_radius;
  }
  options.use_nonmonotonic_steps = o->nonmonotonic_steps != 0;
  options.jacobi_scaling = o->jacobi_scaling != 0;
  options.check_gradients = false;
  options.linear_solver_type = o->normal_equations ? ceres::DENSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
  options.max_num_iterations = o->max_iterations;
  options.function_tolerance = o->function_tolerance;
  options.gradient_tolerance = o->gradient_tolerance;
  options.parameter_tolerance = o->parameter_tolerance;
  options.num_threads = o->n_threads > 0 ? o->n_threads : 1;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  // Ceres reports line-search trouble through glog; the summary says what
  // matters, so glog stays quiet below FATAL.
  FLAGS_minloglevel = google::GLOG_FATAL;
  ceres::Solver::Summary summary;
  auto start = std::chrono::steady_clock::now();
  ceres::Solve(options, &p->problem, &summary);
  s->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s->initial_cost = summary.initial_cost;
  s->final_cost = summary.final_cost;
  s->iterations = (int)summary.iterations.size() > 0 ? (int)summary.iterations.size() - 1 : 0;
  s->successful_steps = summary.num_successful_steps;
  s->n_residuals = summary.num_residuals;
  s->n_parameters = summary.num_parameters;
  switch (summary.termination_type) {
    case ceres::CONVERGENCE:
    case ceres::USER_SUCCESS: s->termination = SF_LSQ_CONVERGENCE; break;
    case ceres::NO_CONVERGENCE: s->termination = SF_LSQ_NO_CONVERGENCE; break;
    default: s->termination = SF_LSQ_FAILURE; break;
  }
  s->usable = summary.IsSolutionUsable() ? 1 : 0;
  std::strncpy(s->message, summary.message.c_str(), sizeof s->message - 1);
  return s->usable ? 0 : 1;
}

int sf_lsq_cost(sf_lsq_problem *p, double *cost) {
  return p->problem.Evaluate(ceres::Problem::EvaluateOptions(), cost, nullptr, nullptr, nullptr)
             ? 0
             : 1;
}

}  // extern "C"
