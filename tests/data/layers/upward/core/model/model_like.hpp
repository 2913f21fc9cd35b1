// A lower floor that includes a higher one: the layering check must refuse it.
#pragma once
#include "app/runner_like.hpp"
