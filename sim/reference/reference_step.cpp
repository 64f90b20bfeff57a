// The readable reference step (sim/reference/reference_step.hpp), compiled once for 2D and 3D in
// float and double, at the solver's optimisation: the bench compares the two steps built alike.
#include "sim/reference/reference_step.hpp"

#include "sim/reference/reference_run.hpp"
#include "sim/reference/reference_setup.hpp"

namespace apiclab::reference {

template void step<float, 2>(const Setup<float, 2>&, ParticleState<float, 2>&, float);
template void step<double, 2>(const Setup<double, 2>&, ParticleState<double, 2>&, double);
template void step<float, 3>(const Setup<float, 3>&, ParticleState<float, 3>&, float);
template void step<double, 3>(const Setup<double, 3>&, ParticleState<double, 3>&, double);

namespace {

template <class T, int D>
class RunOf final : public ReferenceRun {
 public:
  RunOf(const SceneDesc& scene, const Particles<T, D>& p)
      : setup_(setup_of<T, D>(scene)), state_(state_of(p)) {}
  void step(double dt) override { reference::step<T, D>(setup_, state_, T(dt)); }
  bool finite() const override {
    for (const auto& x : state_.x)
      if (!x.allFinite()) return false;
    return true;
  }
  std::size_t particle_count() const override { return state_.x.size(); }

 private:
  Setup<T, D> setup_;
  ParticleState<T, D> state_;
};

}  // namespace

template <class T, int D>
std::unique_ptr<ReferenceRun> run_of(const SceneDesc& scene, const Particles<T, D>& p) {
  return std::make_unique<RunOf<T, D>>(scene, p);
}
template std::unique_ptr<ReferenceRun> run_of(const SceneDesc&, const Particles<float, 2>&);
template std::unique_ptr<ReferenceRun> run_of(const SceneDesc&, const Particles<double, 2>&);
template std::unique_ptr<ReferenceRun> run_of(const SceneDesc&, const Particles<float, 3>&);
template std::unique_ptr<ReferenceRun> run_of(const SceneDesc&, const Particles<double, 3>&);

}  // namespace apiclab::reference
