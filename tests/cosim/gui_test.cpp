// `stsim highway SCENARIO --gui`: sumo-gui launched through libtraci, run unattended on a virtual
// X display (xvfb-run), with the cells drawn as polygons. Skipped only where xvfb-run is missing
// (tools/install-deps.sh installs it).
#include <gtest/gtest.h>

#include "test_util.hpp"
#include <stcosim/backend.hpp>
#include <stcosim/plugin.hpp>
#include <stcosim/scenario.hpp>

namespace st::cosim {
namespace {

using namespace st::cosim::test;

TEST(HighwayGui, SumoGuiRunsUnattendedWithTheEmbeddedRunsWarningsAndDrawsEveryCell) {
  const std::string xvfb = onPath("xvfb-run");
  if (xvfb.empty()) GTEST_SKIP() << "xvfb-run is not installed (Debian package xvfb): no X display for sumo-gui";
  const auto dir = freshDir("gui");
  // to 232 s: the motorway's first four collisions happen between 210 and 231 s
  const std::vector<std::string> common{"highway", motorway().string(), "--end", "232"};

  // sumo-gui must start, run and quit by itself (--start --quit-on-end), or this never returns
  auto gui = common;
  gui.insert(gui.end(), {"--gui", "--out", (dir / "gui").string()});
  const auto g = runStsim(gui, dir, {xvfb, "-a"});
  ASSERT_EQ(g.code, 0) << g.err << " (sumo-gui's log: " << slurp(dir / "gui/sumo.log") << ")";

  auto embedded = common;
  embedded.insert(embedded.end(), {"--out", (dir / "embedded").string()});
  const auto e = runStsim(embedded, dir);
  ASSERT_EQ(e.code, 0) << e.err;

  // the same SUMO run seen through libtraci from sumo-gui: the same warnings, byte for byte
  std::size_t rows = 0;
  EXPECT_TRUE(validWarningsCsv(dir / "gui/warnings.csv", &rows));
  EXPECT_GT(rows, 10u);
  EXPECT_EQ(slurp(dir / "gui/warnings.csv"), slurp(dir / "embedded/warnings.csv"));
  const std::string gs = slurp(dir / "gui/summary.json");
  const std::string es = slurp(dir / "embedded/summary.json");
  EXPECT_EQ(jsonString(gs, "stop_reason"), "end");
  EXPECT_DOUBLE_EQ(jsonNumber(gs, "steps"), 2320.0);
  // SUMO itself says it has a GUI (libtraci's hasGUI)
  EXPECT_NE(jsonString(gs, "backend").find("sumo-gui"), std::string::npos) << jsonString(gs, "backend");
  EXPECT_DOUBLE_EQ(jsonNumber(gs, "color_changes"), jsonNumber(es, "color_changes"));
  EXPECT_GT(jsonNumber(gs, "color_changes"), 0.0);

  // SUMO's collisions: libtraci 1.15 cannot fetch them, so they come from SUMO's collision file;
  // the same rows as libsumo's getCollisions in the embedded run (the file has SUMO's 2 decimals)
  EXPECT_GE(jsonNumber(es, "sumo_collisions"), 2.0);
  EXPECT_DOUBLE_EQ(jsonNumber(gs, "sumo_collisions"), jsonNumber(es, "sumo_collisions"));
  EXPECT_DOUBLE_EQ(jsonNumber(gs, "sumo_collision_steps"), jsonNumber(es, "sumo_collision_steps"));
  const auto gc = lines(slurp(dir / "gui/collisions.csv")), ec = lines(slurp(dir / "embedded/collisions.csv"));
  ASSERT_EQ(gc.size(), ec.size());
  ASSERT_GT(gc.size(), 5u);
  for (std::size_t i = 1; i < gc.size(); ++i) {
    const auto gf = splitCsv(gc[i]), ef = splitCsv(ec[i]);
    ASSERT_EQ(gf.size(), 10u) << gc[i];
    ASSERT_EQ(ef.size(), 10u) << ec[i];
    for (int k : {0, 1, 2, 3, 4}) EXPECT_EQ(gf[k], ef[k]) << "row " << i << ": " << gc[i] << " vs " << ec[i];
    for (int k : {5, 6, 7}) EXPECT_NEAR(std::stod(gf[k]), std::stod(ef[k]), 0.0051) << "row " << i;
  }
  // each collision's lead time: the same either way, and the collider's warning row in warnings.csv
  // (ego, foe, kind, zone, begin, ...) that it counts from
  const std::string leads = slurp(dir / "embedded/collision_warnings.csv");
  EXPECT_EQ(slurp(dir / "gui/collision_warnings.csv"), leads);
  const auto leadRows = lines(leads);
  // one row per collision, a contact (SUMO's minGap violations are not collisions)
  ASSERT_EQ(leadRows.size(), 1 + static_cast<std::size_t>(jsonNumber(es, "contacts")));
  EXPECT_DOUBLE_EQ(jsonNumber(gs, "contacts"), jsonNumber(es, "contacts"));
  EXPECT_DOUBLE_EQ(jsonNumber(gs, "mingap_violations"), jsonNumber(es, "mingap_violations"));
  const auto warningRows = lines(slurp(dir / "embedded/warnings.csv"));
  for (std::size_t i = 1; i < leadRows.size(); ++i) {
    const auto f = splitCsv(leadRows[i]);
    ASSERT_EQ(f.size(), 5u) << leadRows[i];
    if (f[3] != "1") continue;
    bool found = false;
    for (const auto& w : warningRows) {
      const auto wf = splitCsv(w);
      if (wf.size() > 4 && wf[0] == f[1] && wf[1] == f[2] && wf[2] == "vehicle")
        found |= std::abs(std::stod(f[0]) - std::stod(f[4]) - std::stod(wf[4])) < 1e-6;
    }
    EXPECT_TRUE(found) << "no warning of " << f[1] << " about " << f[2] << " begins " << f[4] << " s before " << f[0];
  }
  EXPECT_DOUBLE_EQ(jsonNumber(gs, "collisions_warned"), jsonNumber(es, "collisions_warned"));

  // one polygon per cell in SUMO (cell_polygons is the count sumo-gui reports holding after the
  // drawing), against the cell count of a monitor built here on the same network
  Scenario s = loadScenario(motorway());
  s.end = 1.0;
  auto b = startLibsumo(SumoLaunch{sumoArguments(s), false, "", ""});
  const int cells = HighwayPlugin(*b, s.plugin).monitor().cells().cellCount();
  b->close();
  EXPECT_GE(cells, 15);
  EXPECT_DOUBLE_EQ(jsonNumber(gs, "cell_polygons"), static_cast<double>(cells));
  EXPECT_DOUBLE_EQ(jsonNumber(es, "cell_polygons"), 0.0);  // nothing drawn without a GUI
}

}  // namespace
}  // namespace st::cosim
