#pragma once
// SUMO validates its XML inputs against the schemas under $SUMO_HOME/data/xsd; without SUMO_HOME
// it tries to fetch them from the web and, offline, rejects every input. Call before starting SUMO
// (libsumo or a sumo process) from your own program; stsim's backends call it themselves.
namespace st::cosim {

// If SUMO_HOME is unset and Debian's /usr/share/sumo exists, sets it (for this process and the
// SUMO processes it starts).
void ensureSumoHome();

}  // namespace st::cosim
