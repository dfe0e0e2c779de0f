#include <sthighway/cells.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>

#include <stcore/static_grid.hpp>
#include <sthighway/tolerances.hpp>

namespace st::highway {

namespace {

double polylineLength(const std::vector<Vec2>& pts) {
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) s += (pts[i + 1] - pts[i]).norm();
  return s;
}

Vec2 pointAt(const std::vector<Vec2>& pts, double along) {
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    const double l = (pts[i + 1] - pts[i]).norm();
    if (along <= l || i + 2 == pts.size()) return l > 0.0 ? Vec2(pts[i] + (pts[i + 1] - pts[i]) * std::min(1.0, along / l)) : pts[i];
    along -= l;
  }
  return pts.front();
}

// Bounding box of the part of a polyline between two distances along it.
void growByPortion(Aabb<2>& box, bool& first, const std::vector<Vec2>& pts, double s0, double s1, double pad) {
  auto add = [&](const Vec2& p) {
    const Vec2 lo = p.array() - pad, hi = p.array() + pad;
    if (first) {
      box = {lo, hi};
      first = false;
    } else {
      box.min = box.min.cwiseMin(lo);
      box.max = box.max.cwiseMax(hi);
    }
  };
  add(pointAt(pts, s0));
  add(pointAt(pts, s1));
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    if (s > s0 && s < s1) add(pts[i]);
    s += (pts[i + 1] - pts[i]).norm();
  }
}

Aabb<2> grown(const Aabb<2>& b, double m) { return {b.min.array() - m, b.max.array() + m}; }
Aabb<2> unite(const Aabb<2>& a, const Aabb<2>& b) { return {a.min.cwiseMin(b.min), a.max.cwiseMax(b.max)}; }
bool inside(const Aabb<2>& inner, const Aabb<2>& outer) {
  return (inner.min.array() >= outer.min.array()).all() && (inner.max.array() <= outer.max.array()).all();
}

}  // namespace

struct CellNetwork::Impl {
  static constexpr int kRivals = 4;  // other sites a car tests exactly between measurements
  struct Cell {
    Aabb<2> region;            // its share of road (static)
    Aabb<2> extent;            // region united with its members' fat boxes (per tick)
    Aabb<2> indexed;           // the box the network index holds (extent, grown)
    Aabb<2> treeBounds;        // of its tree, when it has one
    // its members' fat boxes in a tree while it holds more than the decomposition factor (a
    // jam); none otherwise: the pair search sweeps an undivided cell's members itself
    std::optional<Space<2>> tree;
    std::vector<int> slots;    // local slot -> vehicle
    std::vector<int> freeSlots;
    int members = 0;
  };
  struct Served {
    int cell = -1;
    int local = -1;
    Aabb<2> fat;
    // where the car last measured every site, the few other sites nearest it there (-1: none),
    // and a lower bound on its distance from there to every other site but those (m, <= 0:
    // none): while none of the few is stronger by the hysteresis margin (tested exactly, as a
    // handoff would) and the car stays near enough for the rest, no site can take it, so the
    // sites need not be measured again. The nearest other site is often beside the road (the
    // other carriageway's), never stronger, yet it bounded every site and cost a measurement
    // every few metres.
    Vec2 measuredAt = Vec2::Zero();
    double othersAway = 0.0;
    std::array<int, kRivals> rivals{-1, -1, -1, -1};
  };

  CellConfig cfg;
  std::vector<std::string> sections;
  std::vector<CellSite> sites;
  std::vector<Cell> cells;
  std::vector<Served> vehicles;
  Space<2> index;
  StaticGrid<2> siteGrid;  // for "which sites does a car hear"
  double ratioSq = 1.0;  // (d_old / d_new)^2 above which the hysteresis margin is passed
  CellCounters counters;
  SpaceCounters retired;  // of the trees of cells that have since reunited
  SpaceRule treeRule;
  std::vector<Handoff> handoffs;

  Impl(const CellConfig& c, const Aabb<2>& bounds)
      : cfg(c), index(SpaceKind::Cells, grown(bounds, c.cellLength), SpaceRule{8, false, 0, 1, indexCellSize(c, bounds)}) {}

  // The network level is a uniform grid of about one cell length (coarser on huge networks).
  static double indexCellSize(const CellConfig& c, const Aabb<2>& bounds) {
    return gridCellSize<2>(grown(bounds, c.cellLength).extent(), c.cellLength, kMaxGridCells);
  }

  double distSq(int cell, const Vec2& p) const {
    const double d0 = cfg.referenceDistance;
    return std::max((sites[cell].position - p).squaredNorm(), d0 * d0);
  }

  // The strongest site the car hears (nearest: path loss grows with distance); the nearest of
  // all if none is in range, so a car is never lost.
  int strongest(const Vec2& p) const {
    int best = -1;
    double bestD = std::numeric_limits<double>::infinity();
    const StaticGrid<2>::Index g = siteGrid.cellOf(p);
    const int gx = g.x(), gy = g.y();
    const double range2 = cfg.radioRange * cfg.radioRange;
    auto scan = [&](int x, int y) {
      for (int s : siteGrid.objectsIn(StaticGrid<2>::Index(x, y))) {
        const double d = distSq(s, p);
        if (d <= range2 && (d < bestD || (d == bestD && s < best))) {
          bestD = d;
          best = s;
        }
      }
    };
    // rings of grid squares outwards: every site beyond ring k is at least k squares away, so
    // the search stops once the best is nearer than that
    for (int k = 0;; ++k) {
      if (k == 0) {
        scan(gx, gy);
      } else {
        for (int i = -k; i <= k; ++i) {
          scan(gx + i, gy - k);
          scan(gx + i, gy + k);
        }
        for (int j = -k + 1; j <= k - 1; ++j) {
          scan(gx - k, gy + j);
          scan(gx + k, gy + j);
        }
      }
      const double reach = k * siteGrid.cellSize();
      if (best >= 0 && bestD < reach * reach) return best;
      if (reach > cfg.radioRange + siteGrid.cellSize()) break;
    }
    if (best >= 0) return best;
    for (int s = 0; s < static_cast<int>(sites.size()); ++s) {
      const double d = distSq(s, p);
      if (d < bestD) {
        bestD = d;
        best = s;
      }
    }
    return best;
  }

  // The kRivals sites but `cell` nearest p in the grid squares around it, nearest first, and a
  // lower bound on the distance from p to every other site: the nearest of the rest there, or
  // the distance beyond which the unscanned squares lie (0 off the grid: no bound).
  double rivalsAndBound(int cell, const Vec2& p, std::array<int, kRivals>& rivals) const {
    rivals.fill(-1);
    const StaticGrid<2>::Index g = siteGrid.cellOf(p);
    if (!siteGrid.inGrid(g)) return 0.0;
    std::array<double, kRivals> near;
    near.fill(std::numeric_limits<double>::infinity());
    double best = siteGrid.cellSize();  // every site outside the 3 x 3 squares around p is at least this far
    for (int x = g.x() - 1; x <= g.x() + 1; ++x)
      for (int y = g.y() - 1; y <= g.y() + 1; ++y) {
        for (int site : siteGrid.objectsIn(StaticGrid<2>::Index(x, y))) {
          if (site == cell) continue;
          // insert among the nearest; the one pushed out (or this one) joins the rest
          double d = (sites[site].position - p).norm();
          for (int k = 0; k < kRivals && site >= 0; ++k)
            if (d < near[k]) {
              std::swap(d, near[k]);
              std::swap(site, rivals[k]);
            }
          if (site >= 0) best = std::min(best, d);
        }
      }
    return best;
  }

  // True if no site can take the car from its serving cell at p: its serving site's power
  // exceeds every other's less the margin (d_serving^2 <= ratio^2 d_other^2): for the rivals
  // the handoff's own test, for the rest with d_other bounded below by the distance measured at
  // measuredAt less the distance moved since.
  bool keepsServingCell(const Served& s, const Vec2& p) const {
    if (s.othersAway <= 0.0) return false;
    const double serving = distSq(s.cell, p);
    for (int r : s.rivals)
      if (r >= 0 && serving > ratioSq * distSq(r, p)) return false;
    const double away = (s.othersAway - (p - s.measuredAt).norm()) * (1.0 - tol::kBoundRelativeSlop);
    return away > 0.0 && serving <= ratioSq * away * away;
  }

  // A change to one cell's space and slot table. place() makes it at once; placeDeferred()
  // queues it, and commit() makes the queued ones grouped by cell, each cell's in queue order.
  struct Move {
    enum Kind { Leave, Join, Update };
    int cell;
    Kind kind;
    int v;        // Join: the vehicle, which learns its local slot
    int local;    // Leave, Update
    Aabb<2> fat;  // Join, Update (Leave: unused)
  };
  std::vector<Move> moves;     // deferred, in the order placed
  std::vector<Move> byCell;    // scratch: the same, grouped by cell (a stable counting sort)
  std::vector<int> moveStart;  // scratch

  void apply(const Move& mv) {
    Cell& c = cells[mv.cell];
    switch (mv.kind) {
      case Move::Leave:
        if (c.tree) c.tree->remove(mv.local);
        c.slots[mv.local] = -1;
        c.freeSlots.push_back(mv.local);
        --c.members;
        break;
      case Move::Join: {
        int local;
        if (!c.freeSlots.empty()) {
          local = c.freeSlots.back();
          c.freeSlots.pop_back();
          c.slots[local] = mv.v;
        } else {
          local = static_cast<int>(c.slots.size());
          c.slots.push_back(mv.v);
        }
        vehicles[mv.v].local = local;
        if (c.tree) c.tree->insert(local, mv.fat);
        ++c.members;
        break;
      }
      case Move::Update:
        if (c.tree) c.tree->update(mv.local, mv.fat);
        break;
    }
    ++counters.boxChanges;
  }

  void submit(const Move& mv, bool defer) {
    if (defer) moves.push_back(mv);
    else apply(mv);
  }

  void commit() {
    if (moves.empty()) return;
    const int nc = static_cast<int>(cells.size());
    moveStart.assign(nc + 1, 0);
    for (const Move& mv : moves) ++moveStart[mv.cell + 1];
    for (int c = 0; c < nc; ++c) moveStart[c + 1] += moveStart[c];
    byCell.resize(moves.size());
    for (const Move& mv : moves) byCell[moveStart[mv.cell]++] = mv;
    for (const Move& mv : byCell) apply(mv);
    moves.clear();
  }

  // the box grown by the margin and stretched to where the velocity takes it within the lookahead
  Aabb<2> fatOf(const Aabb<2>& box, const Vec2& velocity) const {
    const Vec2 ahead = velocity * cfg.fatLookahead;
    return grown({box.min + ahead.cwiseMin(0.0), box.max + ahead.cwiseMax(0.0)}, cfg.fatMargin);
  }

  // the local slot is -1 from a deferred join to its commit
  void join(int v, int cell, const Aabb<2>& box, const Vec2& velocity, bool defer) {
    Served& s = vehicles[v];
    s.cell = cell;
    s.local = -1;
    s.fat = fatOf(box, velocity);
    submit({cell, Move::Join, v, -1, s.fat}, defer);
  }

  void leave(int v, bool defer) {
    Served& s = vehicles[v];
    submit({s.cell, Move::Leave, v, s.local, s.fat}, defer);  // the box is unused
    s.cell = -1;
    s.local = -1;
  }

  // A cell's tree exists while it holds more cars than the decomposition factor: built from its
  // members in slot order when it passes it, dropped (its counters kept) when it falls back.
  void settleTree(Cell& c) {
    const int df = treeRule.decompositionFactor;
    if (!c.tree && c.members > df) {
      c.tree.emplace(SpaceKind::Tree, c.treeBounds, treeRule);
      for (int local = 0; local < static_cast<int>(c.slots.size()); ++local)
        if (c.slots[local] >= 0) c.tree->insert(local, vehicles[c.slots[local]].fat);
    } else if (c.tree && c.members <= df) {
      retired.subdivisions += c.tree->counters().subdivisions;
      retired.reunions += c.tree->counters().reunions;
      c.tree.reset();
    }
  }

  int place(int v, const Vec2& centre, const Aabb<2>& box, const Vec2& velocity, bool defer) {
    if (v >= static_cast<int>(vehicles.size())) vehicles.resize(v + 1);
    Served& s = vehicles[v];
    if (s.cell >= 0 && s.local < 0) commit();  // placed twice: its join first
    if (s.cell < 0 || !keepsServingCell(s, centre)) {
      const int best = strongest(centre);
      const int from = s.cell;
      if (from < 0) {
        join(v, best, box, velocity, defer);
        ++counters.attaches;
      } else if (best != from && distSq(from, centre) > ratioSq * distSq(best, centre)) {
        // the car tells its old cell, which hands it to the stronger one
        leave(v, defer);
        join(v, best, box, velocity, defer);
        ++counters.handoffs;
        handoffs.push_back({v, from, best});
      }
      s.measuredAt = centre;
      s.othersAway = rivalsAndBound(s.cell, centre, s.rivals);
      if (s.cell != from) return best;  // joined a cell: its fat box is new
    }
    if (!inside(box, s.fat)) {
      s.fat = fatOf(box, velocity);
      submit({s.cell, Move::Update, v, s.local, s.fat}, defer);
    }
    return s.cell;
  }
};

CellNetwork::CellNetwork(const RoadGeometry& road, const RoadFeatures& features, const CellConfig& config) {
  if (!(config.cellLength > 0.0) || !(config.radioRange > 0.0) || !(config.pathLossExponent > 0.0) ||
      !(config.referenceDistance > 0.0) || !(config.hysteresisDb >= 0.0) || config.decompositionFactor < 1 ||
      !(config.fatMargin >= 0.0) || !std::isfinite(config.fatMargin) || !(config.fatLookahead >= 0.0) ||
      !std::isfinite(config.fatLookahead))
    throw std::invalid_argument("cells: cellLength, radioRange, pathLossExponent, referenceDistance must be positive, "
                                "hysteresisDb, fatMargin and fatLookahead finite and non-negative, decompositionFactor >= 1");
  impl_ = std::make_unique<Impl>(config, features.bounds);
  Impl& m = *impl_;
  m.sections = features.sections;
  // hysteresis in dB as a ratio of distances: 10 n log10(d_old / d_new) > h
  const double ratio = std::pow(10.0, config.hysteresisDb / (10.0 * config.pathLossExponent));
  m.ratioSq = ratio * ratio;
  // sites along every section's middle lane, one per cellLength
  std::map<std::string, std::vector<const Lane*>> lanesOf;
  for (const Lane& l : road.lanes)
    if (!l.internal) lanesOf[l.edge].push_back(&l);
  // a cell's tree halves along its longest axis (along the road), not into quadrants of mostly
  // empty verge
  m.treeRule = SpaceRule{config.decompositionFactor, true, 2, config.maxDepth, 0.0};
  const double pad = 2.0 * config.fatMargin + 10.0;
  for (int sec = 0; sec < static_cast<int>(m.sections.size()); ++sec) {
    auto& lanes = lanesOf[m.sections[sec]];
    std::sort(lanes.begin(), lanes.end(), [](const Lane* a, const Lane* b) { return a->index < b->index; });
    const Lane& ref = *lanes[lanes.size() / 2];
    const double len = polylineLength(ref.shape);
    const int n = std::max(1, static_cast<int>(std::lround(len / config.cellLength)));
    for (int k = 0; k < n; ++k) {
      CellSite site;
      site.section = sec;
      site.along = (k + 0.5) * len / n;
      site.position = pointAt(ref.shape, site.along);
      Aabb<2> region{site.position, site.position};
      bool first = true;
      for (const Lane* l : lanes) {
        const double ll = polylineLength(l->shape);
        growByPortion(region, first, l->shape, ll * k / n, ll * (k + 1) / n, 0.5 * l->width);
      }
      m.sites.push_back(site);
      m.cells.push_back(Impl::Cell{region, region, region, grown(region, pad), std::nullopt, {}, {}, 0});
    }
  }
  if (m.sites.empty()) {
    // no road: one cell over everything, so the model still runs on bare traces and tests
    CellSite site;
    site.position = features.bounds.center();
    m.sites.push_back(site);
    m.cells.push_back(Impl::Cell{features.bounds, features.bounds, features.bounds, grown(features.bounds, config.cellLength),
                                 std::nullopt, {}, {}, 0});
  }
  // the site grid
  const Vec2 gridOrigin = features.bounds.min.array() - config.radioRange;
  const Vec2 ext = features.bounds.extent().array() + 2.0 * config.radioRange;
  m.siteGrid = StaticGrid<2>(gridOrigin, ext, std::min(config.cellLength, config.radioRange));
  m.siteGrid.build(static_cast<int>(m.sites.size()), [&](int s) {
    return std::optional<Aabb<2>>(Aabb<2>{m.sites[s].position, m.sites[s].position});
  });
  for (int c = 0; c < static_cast<int>(m.cells.size()); ++c) m.index.insert(c, m.cells[c].indexed);
}

CellNetwork::~CellNetwork() = default;
CellNetwork::CellNetwork(CellNetwork&&) noexcept = default;
CellNetwork& CellNetwork::operator=(CellNetwork&&) noexcept = default;

const CellConfig& CellNetwork::config() const { return impl_->cfg; }
int CellNetwork::cellCount() const { return static_cast<int>(impl_->cells.size()); }
const CellSite& CellNetwork::site(int cell) const { return impl_->sites[cell]; }
std::span<const std::string> CellNetwork::sections() const { return impl_->sections; }

double CellNetwork::signalDbm(int cell, const Vec2& p) const {
  const CellConfig& c = impl_->cfg;
  return c.txPowerDbm - 5.0 * c.pathLossExponent * std::log10(impl_->distSq(cell, p) / (c.referenceDistance * c.referenceDistance));
}

int CellNetwork::place(int v, const Vec2& centre, const Aabb<2>& box, const Vec2& velocity) {
  impl_->commit();  // a space sees its changes in the order placed
  return impl_->place(v, centre, box, velocity, false);
}

int CellNetwork::placeDeferred(int v, const Vec2& centre, const Aabb<2>& box, const Vec2& velocity) {
  return impl_->place(v, centre, box, velocity, true);
}

void CellNetwork::commitPlacements() { impl_->commit(); }

void CellNetwork::remove(int v) {
  Impl& m = *impl_;
  if (v < 0 || v >= static_cast<int>(m.vehicles.size()) || m.vehicles[v].cell < 0) return;
  m.commit();
  m.leave(v, false);
  ++m.counters.detaches;
}

int CellNetwork::servingCell(int v) const {
  return v >= 0 && v < static_cast<int>(impl_->vehicles.size()) ? impl_->vehicles[v].cell : -1;
}

void CellNetwork::refreshExtents() {
  Impl& m = *impl_;
  m.commit();
  for (auto& c : m.cells) c.extent = c.region;
  for (const auto& s : m.vehicles)
    if (s.cell >= 0) m.cells[s.cell].extent = unite(m.cells[s.cell].extent, s.fat);
  std::uint64_t subdivisions = 0, reunions = 0;
  for (int i = 0; i < static_cast<int>(m.cells.size()); ++i) {
    auto& c = m.cells[i];
    if (!inside(c.extent, c.indexed)) {
      c.indexed = grown(c.extent, m.cfg.cellLength * 0.25);
      m.index.update(i, c.indexed);
    }
    m.settleTree(c);
    if (c.tree) {
      subdivisions += c.tree->counters().subdivisions;
      reunions += c.tree->counters().reunions;
    }
  }
  subdivisions += m.retired.subdivisions;
  reunions += m.retired.reunions;
  m.counters.subdivisions = subdivisions;
  m.counters.reunions = reunions;
}

std::vector<int> CellNetwork::membersOf(int cell) const {
  std::vector<int> out;
  for (int v : impl_->cells[cell].slots)
    if (v >= 0) out.push_back(v);
  std::sort(out.begin(), out.end());
  return out;
}

Aabb<2> CellNetwork::cellExtent(int cell) const { return impl_->cells[cell].extent; }
const CellCounters& CellNetwork::counters() const { return impl_->counters; }

std::vector<Handoff> CellNetwork::takeHandoffs() {
  std::vector<Handoff> out;
  out.swap(impl_->handoffs);
  return out;
}

const Space<2>& CellNetwork::networkIndex() const { return impl_->index; }
const Space<2>* CellNetwork::cellTree(int cell) const {
  const auto& tree = impl_->cells[cell].tree;
  return tree ? &*tree : nullptr;
}
std::span<const int> CellNetwork::cellSlots(int cell) const { return impl_->cells[cell].slots; }

}  // namespace st::highway
