// The experiments' registry: filled by each experiment file's Registration at static
// initialisation, read (sorted by order key) once main runs.
#include <algorithm>
#include <stdexcept>
#include <utility>

#include "experiments/experiment.h"

namespace physik::experiments {

namespace {

// a function-local static: built on first use, so registrations from other files' static
// initialisers never see it unconstructed (the static initialisation order is unspecified)
std::vector<std::pair<int, Experiment>>& registered() {
  static std::vector<std::pair<int, Experiment>> list;
  return list;
}

std::vector<Experiment> sorted_experiments() {
  std::vector<std::pair<int, Experiment>> list = registered();
  std::sort(list.begin(), list.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Experiment> out;
  for (std::size_t k = 0; k < list.size(); ++k) {
    for (std::size_t j = 0; j < k; ++j) {
      if (list[j].first == list[k].first || list[j].second.name == list[k].second.name) {
        throw std::logic_error("experiments '" + list[j].second.name + "' and '" +
                               list[k].second.name + "' share a name or an order key");
      }
    }
    out.push_back(list[k].second);
  }
  return out;
}

}  // namespace

Registration::Registration(int order, Experiment experiment) {
  registered().emplace_back(order, std::move(experiment));
}

const std::vector<Experiment>& all_experiments() {
  static const std::vector<Experiment> list = sorted_experiments();
  return list;
}

}  // namespace physik::experiments
