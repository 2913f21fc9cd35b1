#include "core/model/signal_model.hpp"

namespace hyfal::stl {

std::vector<SignalInfo> system_signals(const SystemInfo& info) {
  std::vector<SignalInfo> all = info.outputs;
  for (std::size_t i = 0; i < info.input_names.size(); ++i)
    all.push_back({info.input_names[i], i < info.input_units.size() ? info.input_units[i] : "", "input"});
  all.push_back({"safety", "", "s(q, x; p): <= 0 in the unsafe set (reachability as `always (safety > 0)`)"});
  return all;
}

}  // namespace hyfal::stl
