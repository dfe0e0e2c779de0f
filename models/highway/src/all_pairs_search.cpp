// The reference broad phase: every ego against every other car present.
#include "pair_search.hpp"

namespace st::highway::detail {

namespace {

class AllPairsSearch final : public PairSearch {
 public:
  explicit AllPairsSearch(const PairTest& test) : test_(test) {}

  // accelerations bound the pairs under ConstantAcceleration and in a tick where a car brakes to
  // a stop line (as the cell search)
  void prepare() override {
    const VehicleTable& cars = *test_.cars;
    accelerating_ = test_.cfg->detector.motion == MotionModel::ConstantAcceleration;
    for (int s : cars.active) accelerating_ = accelerating_ || cars.body[s].stopAcceleration < 0.0;
  }

  void threatsOf(int e, std::vector<Threat>& out) override {
    if (accelerating_) threatsOfFor<true>(e, out);
    else threatsOfFor<false>(e, out);
  }

 private:
  template <bool kAccel>
  void threatsOfFor(int e, std::vector<Threat>& out) const {
    const VehicleTable& cars = *test_.cars;
    const Vec2 pe = cars.centre[e], ve = cars.vel[e], exe = cars.ext[e];
    const double k = cars.brakeRatio[e];
    for (int f : cars.active)
      if (f != e) test_.considerFoe<kAccel>(e, f, pe, ve, exe, k, out);
  }

  PairTest test_;
  bool accelerating_ = false;
};

}  // namespace

std::unique_ptr<PairSearch> makeAllPairsSearch(const PairTest& test) { return std::make_unique<AllPairsSearch>(test); }

}  // namespace st::highway::detail
