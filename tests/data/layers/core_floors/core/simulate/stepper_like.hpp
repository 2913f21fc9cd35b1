// A fixture: a simulator that reaches up to the witness floor (refused).
#pragma once
#include "core/witness/witness_like.hpp"
