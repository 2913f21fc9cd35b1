// hyfal.BlackBox: a user's model in Python, known only by its simulations (core/black_box.hpp).
#pragma once
#include <memory>

#include "core/black_box.hpp"
#include "python/common.hpp"

namespace hyfal::python {

struct BlackBox {
  BlackBoxSpec spec;
  std::shared_ptr<const System> system;  // make_black_box over the Python function
};


}  // namespace hyfal::python
