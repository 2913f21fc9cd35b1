// One suite that includes another: the layering check must refuse it.
#include "suites/b/b.hpp"
