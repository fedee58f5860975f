#include "glassmap/glass/evidence.hpp"

namespace glassmap::glass {

std::size_t CellEvidence::countGlass() const {
  return static_cast<std::size_t>(std::count_if(label.begin(), label.end(), [](std::uint8_t l) { return isGlass(l); }));
}

std::size_t CellEvidence::countOccupied() const {
  return static_cast<std::size_t>(std::count(label.begin(), label.end(), static_cast<std::uint8_t>(kOccupied)));
}

std::size_t CellEvidence::countObserved() const {
  return static_cast<std::size_t>(
      std::count_if(label.begin(), label.end(), [](std::uint8_t l) { return l != kUnknown; }));
}

void labelByMinimumCost(CellEvidence& e) {
  for (std::size_t i = 0; i < e.cells.size(); ++i) {
    const float* c = e.costs(i);
    e.label[e.cells[i]] = static_cast<std::uint8_t>(std::min_element(c, c + e.num_labels) - c);
  }
}

}  // namespace glassmap::glass
