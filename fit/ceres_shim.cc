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
  for (int b = 0; b < n_blocks; ++b) {
    if (blocks[b] < 0 || blocks[b] >= (int)p->blocks.size()) return -1;
    sizes.push_back(p->sizes[blocks[b]]);
    values.push_back(p->blocks[blocks[b]]);
  }
  p->problem.AddResidualBlock(new CallbackCost(fn, user, n_residuals, sizes),
                              make_loss(loss, loss_scale), values);
  p->n_residuals += n_residuals;
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
