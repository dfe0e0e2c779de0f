#pragma once
// The SUMO file readers' XML scanner (sumo_files.cpp, sumo_signals.cpp): io's one XML reader,
// its errors thrown as InputError naming the file and line.
#include <filesystem>
#include <string>

#include <stio/xml.hpp>
#include <sthighway/sumo_files.hpp>

namespace st::highway::detail {

class XmlScanner : public io::XmlScanner {
 public:
  explicit XmlScanner(const std::filesystem::path& path) : io::XmlScanner(path, io::raiseAs<InputError>) {}
};

using io::number;
using io::optionalNumber;
using io::required;

}  // namespace st::highway::detail
