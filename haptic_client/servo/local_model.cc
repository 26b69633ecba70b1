#include "haptic_client/servo/local_model.h"

#include <algorithm>
#include <chrono>

#include "core/model/configuration.h"

namespace igms {

LocalModel::LocalModel(const ResolvedScene& scene, int max_steps, double budget_us)
    : sim_(scene), max_steps_(max_steps), budget_us_(budget_us),
      environment_(std::any_of(scene.model->parts.begin(), scene.model->parts.end(),
                               [](const ModelPart& p) { return p.free_body; })),
      q_(VectorX::Zero(scene.model->nq)), v_(VectorX::Zero(scene.model->nv)),
      qdd_(VectorX::Zero(scene.model->nv)), q_next_(VectorX::Zero(scene.model->nq)),
      v_mid_(VectorX::Zero(scene.model->nv)) {}

int LocalModel::stepsWithin(const ResolvedScene& scene, double budget_us) {
  Simulation sim(scene);
  InteractionInput push;  // a push at the first link's origin: the coupled step, the dearer one
  push.mode = InteractionMode::Push;
  push.tip_position = sim.linkPoses().back().p;
  for (int k = 0; k < 20; ++k) sim.step(&push);  // warm
  const int n = 100;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < n; ++k) sim.step(&push);
  const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / n;
  return std::clamp(static_cast<int>(budget_us / std::max(us, 1e-3)), 5, 200);
}

void LocalModel::kinematicStep(double h) {
  v_mid_ = v_ + 0.5 * h * qdd_;
  integrateConfiguration(sim_.model(), q_, v_mid_, h, q_next_);
  q_ = q_next_;
  v_ += h * qdd_;
}

bool LocalModel::run(const RobotSample& state, const SentInputs& inputs, int64_t from, int64_t to,
                     std::vector<SE3>& links, std::vector<Motion>* velocities) {
  const auto started = std::chrono::steady_clock::now();
  last_steps_ = 0;
  last_cut_short_ = false;
  last_over_budget_ = false;
  // The first step taken by the model: with free bodies, the first input kept (bodies and contacts
  // throughout); else the first that interacts.
  const int64_t oldest = std::max(from + 1, to - SentInputs::kCapacity + 1);
  int64_t first = environment_ ? oldest : -1;
  for (int64_t s = oldest; first < 0 && s <= to; ++s)
    if (inputs.at(s).mode != InteractionMode::None) first = s;
  if (first < 0) return false;
  const double dt = sim_.scene().dt;
  const int nq = sim_.model().nq, nv = sim_.model().nv;
  for (int i = 0; i < nq; ++i) q_[i] = state.q[static_cast<size_t>(i)];
  for (int i = 0; i < nv; ++i) v_[i] = state.v[static_cast<size_t>(i)];
  for (int i = 0; i < nv; ++i) qdd_[i] = state.qdd[static_cast<size_t>(i)];
  // Up to the first interaction: as the state was going (the server's own trajectory).
  double t = state.sim_time;
  int64_t s = from + 1;
  for (; s < first; ++s, t += dt) kinematicStep(dt);
  sim_.setState(t, q_, v_, qdd_, state.mode != 0);
  // Then the server's step itself, input by input.
  for (; s <= to && last_steps_ < max_steps_; ++s, ++last_steps_) {
    const int64_t unconverged = sim_.contactStats().unconverged;
    if (!sim_.step(&inputs.at(s))) break;
    max_penetration_ = std::max(max_penetration_, sim_.contacts().maxPenetration());
    if (sim_.contactStats().unconverged > unconverged && s < to && last_steps_ + 1 < max_steps_) {
      last_cut_short_ = true;
      ++cut_short_;
      ++s, ++last_steps_;
      break;
    }
    if (budget_us_ > 0.0 && s < to && last_steps_ + 1 < max_steps_ &&
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - started).count() > budget_us_) {
      last_over_budget_ = true;
      ++over_budget_;
      ++s, ++last_steps_;
      break;
    }
  }
  q_ = sim_.q();
  v_ = sim_.v();
  qdd_ = sim_.qdd();
  for (; s <= to; ++s) kinematicStep(dt);  // beyond the budget
  sim_.setState(t, q_, v_, qdd_, false);
  const std::vector<SE3>& poses = sim_.linkPoses();
  std::copy(poses.begin(), poses.end(), links.begin());
  if (velocities) {
    const std::vector<Motion>& w = sim_.linkVelocities();
    std::copy(w.begin(), w.end(), velocities->begin());
  }
  return true;
}

}  // namespace igms
