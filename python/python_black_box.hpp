// hyfal.BlackBox: a user's model in Python, known only by its simulations (core/model/black_box.hpp).
#pragma once
#include <memory>

#include "core/model/black_box.hpp"
#include "python/conversions.hpp"

namespace hyfal::python {

// Whether this thread is running a hyfal.BlackBox's simulate: a falsify() started from there
// would wait on trials that wait on it (the model's thread), so falsify refuses it.
bool inside_model_simulate();

struct BlackBox {
  BlackBoxSpec spec;
  std::shared_ptr<const System> system;  // make_black_box over the Python function
};


}  // namespace hyfal::python
