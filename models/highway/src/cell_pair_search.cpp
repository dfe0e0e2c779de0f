// The cells broad phase. Each tick every car is placed in its serving cell (CellNetwork measures
// the sites and hands it off), and each cell's cars are grouped in two bins: 2 c + 0 for its
// compact cars (light, small, keeping their lane), 2 c + 1 for the rest (heavy or large ones, lane
// changers). The reach of a walk into a bin grows with the bin's largest brake ratio, envelope and
// lateral speed, so the few trucks and lane changers no longer widen every walk into their cell:
// the opposing carriageway's compact bin lies beyond a compact car's reach. Any split gives the
// same threats (the bounds hold per bin); a divided cell keeps all its cars in bin 2 c.
//
// A bin's cars are kept sorted along its long axis (the member arrays). The pairs of cars in
// undivided bins are walked once, from the cars of one bin over the sorted members of the other
// (findPairsOnce); an ego in a divided cell is searched on its own, through the cell's tree for
// divided neighbours and over the members for the others (searchFor).
#include <algorithm>
#include <limits>

#include "index_visit.hpp"
#include "pair_search.hpp"

namespace st::highway::detail {

namespace {

Aabb<2> boxOf(const Body& b) {
  const double c = std::abs(b.axis.x()), s = std::abs(b.axis.y());
  const Vec2 h(c * 0.5 * b.length + s * 0.5 * b.width, s * 0.5 * b.length + c * 0.5 * b.width);
  return {b.position - h, b.position + h};
}

// The first index in [begin, end) where pred turns false (pred true on a prefix), as
// std::partition_point, without a branch in its loop
template <class Pred>
int partitionPoint(int begin, int end, Pred pred) {
  if (begin == end || !pred(begin)) return begin;
  int base = begin;  // pred(base) holds
  for (int n = end - begin; n > 1;) {
    const int half = n / 2;
    base = pred(base + half) ? base + half : base;
    n -= half;
  }
  return base + 1;
}

// Bounds of a bin's members' velocities, accelerations, envelopes and brake ratios.
struct BinStats {
  Vec2 vmin = Vec2::Zero(), vmax = Vec2::Zero();
  double amax = 0.0, envMax = 0.0;
  Vec2 extMax = Vec2::Zero();
  double ratioMax = 0.0;      // largest brake ratio m / (2 F_brake) of its equipped cars (s per m/s)
  double ratioLight = 0.0;    // the largest below ratioMax (0 if none): the lighter cars' own list
  double ratioAll = 0.0;      // largest brake ratio of all its cars, equipped or not
  Aabb<2> centres{Vec2::Zero(), Vec2::Zero()};
  int count = 0;
  int equipped = 0;
  bool divided = false;       // its cell is divided: searched through the cell's tree
  bool stopping = false;      // a member brakes to a stop line
  int axis = 0;               // the long axis of its members' centres

  // an equipped car's brake ratio into ratioMax and ratioLight, without a branch (the trucks come
  // in no order): ratioLight stays the largest ratio below ratioMax
  void takeRatio(double k) {
    const double lo = std::min(k, ratioMax), hi = std::max(k, ratioMax);
    ratioLight = lo < hi ? std::max(ratioLight, lo) : ratioLight;
    ratioMax = hi;
  }
  // takes in another bin's cars (the bounds as if they had been taken one by one)
  void absorb(const BinStats& o) {
    if (o.count == 0) return;
    if (count == 0) {
      *this = o;
      return;
    }
    vmin = vmin.cwiseMin(o.vmin);
    vmax = vmax.cwiseMax(o.vmax);
    centres.min = centres.min.cwiseMin(o.centres.min);
    centres.max = centres.max.cwiseMax(o.centres.max);
    amax = std::max(amax, o.amax);
    envMax = std::max(envMax, o.envMax);
    extMax = extMax.cwiseMax(o.extMax);
    ratioAll = std::max(ratioAll, o.ratioAll);
    // the two largest distinct ratios of the union are among each side's two (0: none)
    takeRatio(o.ratioMax);
    takeRatio(o.ratioLight);
    count += o.count;
    equipped += o.equipped;
  }
};

// A bin as a per-ego search reads it, copied so an ego's search reads one array.
struct Neighbour {
  Vec2 vmin, vmax, extMax;
  Aabb<2> centres;
  double amax;
  int begin, end;  // its members in the member arrays
  int bin;
  int axis;
  bool divided;
};

// The member arrays' data for a walk's locals: through the vectors, every store in the walk (an
// int) could alias their bounds, and the compiler would reload them each iteration.
struct MemberView {
  const double* key;
  const Vec2* pos;
  const Vec2* vel;
  const Vec2* ext;
  const double* acc;
  const int* slot;
  const double* brake;
  const int* equipped;
};

// The walk: members i, i + 1, ... before `end` while their key is <= hi, of which those whose
// centre lies in the reach box cb, whose mask(i) is 1 and whose pair passes the cheap bound at
// brake ratio ratio(i) are written to pass (their member indices); returns how many.
// candidates: sum of count(i, in) over the members walked. Without branches and without a call
// (the loop's state stays in registers): the containment and the bound's outcomes are
// unpredictable.
template <bool kAccel, class Mask, class Count, class Ratio>
[[gnu::always_inline]] inline int walk(const MemberView& mv, int i, int end, double hi, const Aabb<2>& cb, const Vec2& pe,
                                       const Vec2& ve, const Vec2& exe, double accE, double tr, int* pass,
                                       std::uint64_t& candidates, Mask mask, Count count, Ratio ratio) {
  int npass = 0;
  for (; i < end && mv.key[i] <= hi; ++i) {
    const Vec2& q = mv.pos[i];
    const int in = inside(q, cb) & mask(i);
    candidates += count(i, in);
    const Vec2 p = q - pe, v = mv.vel[i] - ve;
    const double accel = kAccel ? accE + mv.acc[i] : 0.0;
    pass[npass] = i;
    npass += in & pairMayWarn<kAccel>(tr, ratio(i), p, v, exe + mv.ext[i], accel);
  }
  return npass;
}

class CellPairSearch final : public PairSearch {
 public:
  CellPairSearch(const PairTest& test, CellNetwork& cells) : test_(test), cells_(&cells) {}

  void prepare() override;
  void threatsOf(int e, std::vector<Threat>& out) override;
  std::span<const CarGroup> groups() const override { return groups_; }
  int groupOf(int slot) const override { return binOf_[slot]; }

 private:
  const VehicleTable& cars() const { return *test_.cars; }
  // accelerations bound the pairs under ConstantAcceleration, and in a tick where a car brakes to
  // a stop line under either model (a leader slowing for its red light closes on its follower)
  bool accelerating() const { return test_.cfg->detector.motion == MotionModel::ConstantAcceleration || anyStop_; }
  MemberView memberView() const {
    return {memberKey_.data(), memberPos_.data(), memberVel_.data(), memberExt_.data(),
            memberAcc_.data(), memberSlot_.data(), memberBrake_.data(), memberEquipped_.data()};
  }
  int* passBuffer(int n) {
    if (static_cast<int>(passed_.size()) < n) passed_.resize(n);
    return passed_.data();
  }

  void placeCars();
  void sortMembers();
  void buildNeighbourLists();
  void buildPairBins();
  void findPairsOnce();
  template <bool kAccel>
  void findPairsOnceFor();
  template <bool kAccel, bool kOwn>
  void walkPairsOnce(int ie, int B, int from);
  template <bool kAccel>
  void searchFor(int e, std::vector<Threat>& out);
  template <bool kAccel>
  void searchDivided(int e, int cell, const Aabb<2>& cb, std::vector<Threat>& out);
  // how far behind and ahead of any car of bin a a member of bin b can lie to meet it within
  // the safe time of brake ratio k: reachOf with every term at its bound over a's cars
  Reach binReach(const BinStats& a, const BinStats& b, double k, bool accel, double slop) const {
    const Vec2 up = (b.vmax - a.vmin).cwiseMax(0.0), down = (a.vmax - b.vmin).cwiseMax(0.0);
    return reachOf(test_.reactionTime(), k, up, down, a.extMax + b.extMax, accel ? a.amax + b.amax : 0.0, slop);
  }

  PairTest test_;
  CellNetwork* cells_;

  std::vector<BinStats> binStats_;
  std::vector<int> binOf_;       // the car's bin, by slot
  std::vector<CarGroup> groups_;  // binStats_ as the road search reads it
  double globalAmax_ = 0.0;
  bool anyStop_ = false;  // a car brakes to a stop line this tick
  Vec2 globalExtMax_ = Vec2::Zero();

  // the cars of every bin, contiguous by bin (memberStart_[b] .. memberStart_[b + 1]), each bin's
  // sorted by (coordinate along its long axis, slot), with copies of the state a walk reads
  std::vector<int> memberStart_;
  std::vector<int> memberNext_;                      // scratch for the counting sorts
  std::vector<std::pair<double, int>> memberOrder_;  // scratch for the sort
  std::vector<double> memberKey_;
  std::vector<Vec2> memberPos_;
  std::vector<Vec2> memberVel_;
  std::vector<Vec2> memberExt_;
  std::vector<double> memberAcc_;
  std::vector<int> memberSlot_;
  std::vector<int> memberSlotBefore_;        // memberSlot_ at the last tick
  std::vector<std::uint64_t> gathered_;      // per slot: the gathering it was placed in
  std::uint64_t gatherStamp_ = 0;
  std::vector<double> memberBrake_;          // m / (2 F_brake)
  std::vector<PairState> memberPairState_;
  std::vector<int> memberEquipped_;          // 1 or 0
  std::vector<int> passed_;                  // scratch: member indices whose pair passed the bound

  // Per bin, this tick. A divided cell's bin lists every bin its cars may meet, an undivided
  // cell's bin only the divided ones (neighbours_); the undivided ones are in nearBins_, their
  // pairs walked once.
  std::vector<std::vector<Neighbour>> neighbours_;
  std::vector<std::vector<Neighbour>> neighboursLight_;  // for the cars with k <= the bin's ratioLight
  std::vector<std::vector<int>> nearBins_;
  std::vector<IndexVisit> cellsVisits_;  // per bin: the network index's cells near it

  // Each pair of cars in undivided bins is walked once: within a bin by the car earlier in the
  // member arrays, between two bins by the cars of the bin with fewer of them (pairBins_); each
  // pair is tested in each direction whose ego is equipped: half the walks of a search per ego.
  // The reach and the bound use the larger brake ratio of the two (the bin's largest for its
  // members), so they hold for both directions; that widens them, yet it measured faster than
  // leaving each pair to its heavier car (reach at the walker's own ratio, but the trucks walk
  // the other bins too), and the bins keep most trucks out of the compact cars' reach. The
  // threats are grouped by ego (pairFound_, a counting sort) for its turn (threatsOf).
  struct PairThreat {
    int ego;
    Threat threat;
  };
  std::vector<PairThreat> pairFound_;
  std::vector<Threat> pairFoundByEgo_;
  std::vector<int> pairFoundStart_;        // per slot, into pairFoundByEgo_
  std::vector<std::vector<int>> pairBins_;  // per bin A: the bins its cars walk (buildPairBins)
};

void CellPairSearch::prepare() {
  for (int s : cars().departed) cells_->remove(s);
  placeCars();
  sortMembers();
  buildNeighbourLists();
  buildPairBins();
  findPairsOnce();
}

// Each car placed, and its bin's statistics taken, in one pass; the spaces change cell by cell at
// the commit (in refreshExtents): in input order consecutive cars are in different cells, and
// each space's tree would be a cache miss.
void CellPairSearch::placeCars() {
  const VehicleTable& t = cars();
  MonitorCounters& counters = *test_.counters;
  const int nc = cells_->cellCount();
  const int nb = 2 * nc;
  binStats_.assign(nb, BinStats{});
  memberStart_.assign(nb + 1, 0);
  if (binOf_.size() < t.slots.size()) binOf_.resize(t.slots.size());
  globalAmax_ = 0.0;
  anyStop_ = false;
  globalExtMax_ = Vec2::Zero();
  for (int s : t.active) {
    const int bin = 2 * cells_->placeDeferred(s, t.body[s].position, boxOf(t.body[s]), t.vel[s]) + t.wide[s];
    binOf_[s] = bin;
    BinStats& c = binStats_[bin];
    const Vec2& v = t.body[s].velocity;
    if (c.count++ == 0) {
      c.vmin = c.vmax = v;
      c.centres = {t.centre[s], t.centre[s]};
    } else {
      c.vmin = c.vmin.cwiseMin(v);
      c.vmax = c.vmax.cwiseMax(v);
      c.centres.min = c.centres.min.cwiseMin(t.centre[s]);
      c.centres.max = c.centres.max.cwiseMax(t.centre[s]);
    }
    ++memberStart_[bin + 1];
    c.amax = std::max(c.amax, t.accelAbs[s]);
    c.envMax = std::max(c.envMax, t.env[s]);
    c.extMax = c.extMax.cwiseMax(t.ext[s]);
    c.ratioAll = std::max(c.ratioAll, t.brakeRatio[s]);
    if (t.equipped[s]) {
      ++c.equipped;
      c.takeRatio(t.brakeRatio[s]);
    }
    globalAmax_ = std::max(globalAmax_, t.accelAbs[s]);
    c.stopping = c.stopping || t.body[s].stopAcceleration < 0.0;
    anyStop_ = anyStop_ || c.stopping;
    globalExtMax_ = globalExtMax_.cwiseMax(t.ext[s]);
  }
  cells_->refreshExtents();
  cells_->takeHandoffs();
  const CellCounters& cc = cells_->counters();
  counters.handoffs = cc.handoffs;
  counters.subdivisions = cc.subdivisions;
  counters.reunions = cc.reunions;
  // a divided cell's cars all in its first bin (searched through its tree)
  for (int c = 0; c < nc; ++c) {
    if (!cells_->divided(c)) continue;
    binStats_[2 * c].absorb(binStats_[2 * c + 1]);
    binStats_[2 * c + 1] = BinStats{};
    binStats_[2 * c].divided = binStats_[2 * c + 1].divided = true;
    memberStart_[2 * c + 1] += memberStart_[2 * c + 2];
    memberStart_[2 * c + 2] = 0;
  }
  groups_.resize(nb);
  for (int b = 0; b < nb; ++b) {
    const BinStats& c = binStats_[b];
    groups_[b] = {c.centres, c.vmin, c.vmax, c.amax, c.envMax, c.ratioMax, c.equipped, c.stopping};
  }
}

// Members contiguous by bin (a counting sort), then each bin's sorted along its long axis.
void CellPairSearch::sortMembers() {
  const VehicleTable& t = cars();
  const int nb = static_cast<int>(binStats_.size());
  for (int b = 0; b < nb; ++b) memberStart_[b + 1] += memberStart_[b];
  const std::size_t na = t.active.size();
  memberOrder_.resize(na);
  memberKey_.resize(na);
  memberPos_.resize(na);
  memberVel_.resize(na);
  memberExt_.resize(na);
  memberAcc_.resize(na);
  std::swap(memberSlot_, memberSlotBefore_);  // last tick's order, for the gathering below
  memberSlot_.resize(na);
  memberBrake_.resize(na);
  memberEquipped_.resize(na);
  memberPairState_.resize(na);
  for (BinStats& cs : binStats_) {
    if (cs.count == 0) continue;
    const Vec2 ext = cs.centres.extent();
    cs.axis = ext.y() > ext.x() ? 1 : 0;
  }
  // gathered in last tick's member order, then the cars new to it: cars keep their order along
  // the road from tick to tick, so each bin's sort (an insertion sort for a few dozen) finds its
  // run nearly in order; the sort's total order decides the result either way
  memberNext_.assign(memberStart_.begin(), memberStart_.end() - 1);
  ++gatherStamp_;
  auto gather = [&](int s) {
    if (gathered_[s] == gatherStamp_) return;
    gathered_[s] = gatherStamp_;
    int bin = binOf_[s];
    if (binStats_[bin].divided) binOf_[s] = bin &= ~1;
    memberOrder_[memberNext_[bin]++] = {t.centre[s][binStats_[bin].axis], s};
  };
  gathered_.resize(t.slots.size());
  for (int s : memberSlotBefore_)
    if (t.inputOf[s] >= 0) gather(s);
  for (int s : t.active) gather(s);
  for (int c = 0; c < nb; ++c) {
    // an insertion sort: the run is nearly in order (std::sort partitions a run past 16 first)
    std::pair<double, int>* run = memberOrder_.data() + memberStart_[c];
    const int count = memberStart_[c + 1] - memberStart_[c];
    for (int i = 1; i < count; ++i) {
      const std::pair<double, int> x = run[i];
      int j = i;
      for (; j > 0 && x < run[j - 1]; --j) run[j] = run[j - 1];
      run[j] = x;
    }
  }
  for (std::size_t i = 0; i < na; ++i) {
    const auto [key, slot] = memberOrder_[i];
    memberKey_[i] = key;
    memberPos_[i] = t.centre[slot];
    memberVel_[i] = t.vel[slot];
    memberExt_[i] = t.ext[slot];
    memberAcc_[i] = t.accelAbs[slot];
    memberSlot_[i] = slot;
    memberBrake_[i] = t.brakeRatio[slot];
    memberEquipped_[i] = t.equipped[slot];
    memberPairState_[i] = t.pairState[slot];
  }
}

// For every bin with equipped cars, the bins whose members any of them could reach within its
// largest safe time: bounds over the two bins' velocities, sizes, accelerations, masses.
void CellPairSearch::buildNeighbourLists() {
  const bool accel = accelerating();
  const int nb = static_cast<int>(binStats_.size());
  neighbours_.resize(nb);
  neighboursLight_.resize(nb);
  nearBins_.resize(nb);
  cellsVisits_.resize(nb);
  // the signed velocity bounds over all cells with cars, for the box below
  Vec2 vHi = Vec2::Constant(-std::numeric_limits<double>::infinity());
  Vec2 vLo = Vec2::Constant(std::numeric_limits<double>::infinity());
  for (const BinStats& c : binStats_)
    if (c.count > 0) {
      vHi = vHi.cwiseMax(c.vmax);
      vLo = vLo.cwiseMin(c.vmin);
    }
  for (int A = 0; A < nb; ++A) {
    neighbours_[A].clear();
    neighboursLight_[A].clear();
    nearBins_[A].clear();
    const BinStats& ca = binStats_[A];
    if (ca.equipped == 0) continue;
    // A box holding every bin's reach below: the reach with every operand at its bound over all
    // bins (the fastest of them behind A, the slowest ahead, the largest acceleration and
    // extent; one more slop for contracted or reordered roundoff). It picks the cells to test
    // from the index and rejects most of them without a square root; the neighbours' order
    // differs from the symmetric box's, and nothing depends on it (the episode book orders
    // threats totally).
    const Vec2 upG = (vHi - ca.vmin).cwiseMax(0.0), downG = (ca.vmax - vLo).cwiseMax(0.0);
    const Reach g = reachOf(test_.reactionTime(), ca.ratioMax, upG, downG, ca.extMax + globalExtMax_,
                            accel ? ca.amax + globalAmax_ : 0.0, 3 * tol::kPruneSlop);
    const Aabb<2> box{ca.centres.min - g.behind, ca.centres.max + g.ahead};
    for (int cellB : cachedVisit(cells_->networkIndex(), box, cellsVisits_[A]))
      for (int B = 2 * cellB; B < 2 * cellB + 2; ++B) {
        const BinStats& cb = binStats_[B];
        if (cb.count == 0 || !box.overlaps(cb.centres)) continue;
        // the reach grows with the brake ratio k: with ratioMax for every car of A, with ratioLight
        // for the cars at or below it (the list they walk is then a subsequence of the full one)
        auto reaches = [&](double k) {
          const Reach r = binReach(ca, cb, k, accel, 2 * tol::kPruneSlop);
          return Aabb<2>{ca.centres.min - r.behind, ca.centres.max + r.ahead}.overlaps(cb.centres);
        };
        if (!reaches(ca.ratioMax)) continue;
        if (!ca.divided && !cb.divided) {
          nearBins_[A].push_back(B);  // its pairs are walked once
          continue;
        }
        const Neighbour entry{cb.vmin, cb.vmax, cb.extMax, cb.centres, cb.amax, memberStart_[B], memberStart_[B + 1], B,
                           cb.axis, cb.divided};
        neighbours_[A].push_back(entry);
        if (ca.ratioLight > 0.0 && reaches(ca.ratioLight)) neighboursLight_[A].push_back(entry);
      }
  }
}

// The bin pairs walked once (both undivided): those where either bin's cars may reach the other's
// (the reach is symmetric but for the brake ratio). The bin with fewer cars walks the other (the
// lower on a tie): a walk's fixed cost (its reach, its search) is paid per walking car, so a
// cell's few wide cars walk its many compact ones rather than the other way round.
void CellPairSearch::buildPairBins() {
  const int nb = static_cast<int>(binStats_.size());
  pairBins_.resize(nb);
  for (int A = 0; A < nb; ++A) pairBins_[A].clear();
  for (int A = 0; A < nb; ++A)
    for (int B : nearBins_[A]) {
      if (B == A) continue;
      const int countA = binStats_[A].count, countB = binStats_[B].count;
      const bool aWalks = countA < countB || (countA == countB && A < B);
      std::vector<int>& list = pairBins_[aWalks ? A : B];
      const int other = aWalks ? B : A;
      if (std::find(list.begin(), list.end(), other) == list.end()) list.push_back(other);
    }
}

void CellPairSearch::findPairsOnce() {
  pairFound_.clear();
  if (accelerating()) findPairsOnceFor<true>();
  else findPairsOnceFor<false>();
  // by ego (slot), a counting sort
  const std::size_t ns = cars().slots.size();
  pairFoundStart_.assign(ns + 1, 0);
  for (const PairThreat& pt : pairFound_) ++pairFoundStart_[pt.ego + 1];
  for (std::size_t s = 0; s < ns; ++s) pairFoundStart_[s + 1] += pairFoundStart_[s];
  pairFoundByEgo_.resize(pairFound_.size());
  memberNext_.assign(pairFoundStart_.begin(), pairFoundStart_.end() - 1);
  for (const PairThreat& pt : pairFound_) pairFoundByEgo_[memberNext_[pt.ego]++] = pt.threat;
}

template <bool kAccel>
void CellPairSearch::findPairsOnceFor() {
  for (int A = 0; A < static_cast<int>(binStats_.size()); ++A) {
    const BinStats& ca = binStats_[A];
    if (ca.count == 0 || ca.divided) continue;
    const int first = memberStart_[A], last = memberStart_[A + 1];
    if (ca.equipped > 0)
      for (int i = first; i < last; ++i) walkPairsOnce<kAccel, true>(i, A, i + 1);
    for (int B : pairBins_[A]) {
      const BinStats& cb = binStats_[B];
      // the cars of A whose reach box (walkPairsOnce's) may meet B's centres: a run along A's
      // sorted axis; the rest are skipped without computing their reach
      // (named copies, not a structured binding: the lambdas below capture them, which clang 14 refuses)
      const Reach reach = binReach(ca, cb, std::max(ca.ratioAll, cb.ratioMax), kAccel, tol::kPruneSlop);
      const Vec2 behind = reach.behind, ahead = reach.ahead;
      const int a = ca.axis, o = 1 - a;
      // (each test is monotone along the sorted keys: a binary search for where it turns)
      const double* key = memberKey_.data();
      const int lo = partitionPoint(first, last, [&](int i) { return !(key[i] + ahead[a] >= cb.centres.min[a]); });
      const int hi = partitionPoint(first, last, [&](int i) { return key[i] - behind[a] <= cb.centres.max[a]; });
      const bool anyEgo = cb.equipped > 0;
      for (int i = lo; i < hi; ++i) {
        const double q = memberPos_[i][o];
        if (q - behind[o] <= cb.centres.max[o] && q + ahead[o] >= cb.centres.min[o] && (anyEgo || memberEquipped_[i]))
          walkPairsOnce<kAccel, false>(i, B, memberStart_[B]);
      }
    }
  }
}

// The car at member index ie against bin B's members from index `from` on. kOwn: B is the car's
// own bin, `from` the next member: its reach holds the car's centre and starts before it along
// the sorted axis (no overlap test, no search).
template <bool kAccel, bool kOwn>
[[gnu::always_inline]] inline void CellPairSearch::walkPairsOnce(int ie, int B, int from) {
  const BinStats& c = binStats_[B];
  // the car's state from the member arrays (copies of its slot's, in walk order: the slot arrays
  // in this order would be a cache miss a car)
  const MemberView mv = memberView();
  const int e = mv.slot[ie];
  const int equippedE = mv.equipped[ie];
  const double kE = mv.brake[ie];
  const Vec2 pe = mv.pos[ie], ve = mv.vel[ie], exe = mv.ext[ie];
  const double accE = kAccel ? mv.acc[ie] : 0.0;
  const double tr = test_.reactionTime();
  const Aabb<2> cb = reachBoxOf<kAccel>(tr, pe, ve, exe, accE, std::max(kE, c.ratioMax), c.vmin, c.vmax, c.extMax, c.amax);
  if (!kOwn && !c.centres.overlaps(cb)) return;
  const int end = memberStart_[B + 1];
  const int i = kOwn ? from : partitionPoint(from, end, [&](int m) { return mv.key[m] < cb.min[c.axis]; });
  int* pass = passBuffer(end - from);
  std::uint64_t candidates = 0;
  // a pair counts once per equipped ego
  const int npass = walk<kAccel>(
      mv, i, end, cb.max[c.axis], cb, pe, ve, exe, accE, tr, pass, candidates,
      [&](int m) { return equippedE | mv.equipped[m]; },
      [&](int m, int in) { return static_cast<unsigned>(in * (equippedE + mv.equipped[m])); },
      [&](int m) { return std::max(kE, mv.brake[m]); });
  test_.counters->candidatePairs += candidates;
  // each direction with its own ego's bound, then the exact test (the same arithmetic as the
  // per-ego search: p and v from the ego's side)
  for (int j = 0; j < npass; ++j) {
    const int m = pass[j];
    const Vec2 p = mv.pos[m] - pe, v = mv.vel[m] - ve;
    const double accel = kAccel ? accE + mv.acc[m] : 0.0;
    const bool askE = equippedE && pairMayWarn<kAccel>(tr, kE, p, v, exe + mv.ext[m], accel);
    const bool askF = mv.equipped[m] && pairMayWarn<kAccel>(tr, mv.brake[m], p, v, exe + mv.ext[m], accel);
    if (!askE && !askF) continue;
    const int f = mv.slot[m];
    Threat te, tf;
    const int warns = test_.pairThreats(e, f, memberPairState_[ie], memberPairState_[m], p, v, accel, askE, askF, te, tf);
    if (warns & 1) pairFound_.push_back({e, te});
    if (warns & 2) pairFound_.push_back({f, tf});
  }
}

// Ego e's vehicle threats: in an undivided bin, those its pairs walked once found, then the foes
// in divided neighbour cells; in a divided one, a search of its own. The order does not matter:
// the episode book orders the threats totally.
void CellPairSearch::threatsOf(int e, std::vector<Threat>& out) {
  const int own = binOf_[e];
  const bool divided = binStats_[own].divided;
  if (!divided) {
    out.insert(out.end(), pairFoundByEgo_.begin() + pairFoundStart_[e], pairFoundByEgo_.begin() + pairFoundStart_[e + 1]);
    if (neighbours_[own].empty()) return;  // no divided neighbour
  }
  if (accelerating()) searchFor<true>(e, out);
  else searchFor<false>(e, out);
}

// Ego e against the bins in its neighbour list (only divided bins when its own is undivided).
template <bool kAccel>
void CellPairSearch::searchFor(int e, std::vector<Threat>& out) {
  const VehicleTable& t = cars();
  const Vec2 pe = t.centre[e], ve = t.vel[e], exe = t.ext[e];
  const double accE = kAccel ? t.accelAbs[e] : 0.0;
  const double tr = test_.reactionTime(), k = t.brakeRatio[e];
  const int own = binOf_[e];
  for (const Neighbour& c : k <= binStats_[own].ratioLight ? neighboursLight_[own] : neighbours_[own]) {
    const Aabb<2> cb = reachBoxOf<kAccel>(tr, pe, ve, exe, t.accelAbs[e], k, c.vmin, c.vmax, c.extMax, c.amax);
    // the reach bounds foe centres: skip a bin none of whose members' centres is inside
    if (!c.centres.overlaps(cb)) continue;
    // a divided cell is searched through its tree; an undivided bin through its members sorted
    // along its long axis (from the first inside the reach's range)
    if (c.divided) {
      searchDivided<kAccel>(e, c.bin / 2, cb, out);
      continue;
    }
    const MemberView mv = memberView();
    const int i = partitionPoint(c.begin, c.end, [&](int m) { return mv.key[m] < cb.min[c.axis]; });
    int* pass = passBuffer(c.end - c.begin);
    std::uint64_t candidates = 0;
    const int npass = walk<kAccel>(
        mv, i, c.end, cb.max[c.axis], cb, pe, ve, exe, accE, tr, pass, candidates,
        [&](int m) { return static_cast<int>(mv.slot[m] != e); },
        [](int, int in) { return static_cast<unsigned>(in); }, [&](int) { return k; });
    test_.counters->candidatePairs += candidates;
    for (int j = 0; j < npass; ++j) {
      const int m = pass[j];
      test_.checkPair(e, mv.slot[m], mv.pos[m] - pe, mv.vel[m] - ve, kAccel ? accE + mv.acc[m] : 0.0, out);
    }
  }
}

// Ego e against the members of a divided cell whose centres lie in its reach box cb, found
// through the cell's tree.
template <bool kAccel>
void CellPairSearch::searchDivided(int e, int cell, const Aabb<2>& cb, std::vector<Threat>& out) {
  const VehicleTable& t = cars();
  cells_->forEachInCellBox(cell, cb, [&](int f) {
    if (f != e && cb.contains(t.centre[f]))
      test_.considerFoe<kAccel>(e, f, t.centre[e], t.vel[e], t.ext[e], t.brakeRatio[e], out);
  });
}

}  // namespace

std::unique_ptr<PairSearch> makeCellPairSearch(const PairTest& test, CellNetwork& cells) {
  return std::make_unique<CellPairSearch>(test, cells);
}

}  // namespace st::highway::detail
