#include <stpool/study.hpp>

#include <stdexcept>

namespace st::pool {

void printFig13Study(std::ostream&) { throw std::runtime_error("the fig13 study is not implemented yet"); }

}  // namespace st::pool
