#pragma once
// The explicit dynamic MPM solver, mpm::Solver: declared in mpm/explicit/solver.hpp, its stages in
// mpm/explicit/. This header keeps the path callers outside mpm/ include.
#include "pilempm/mpm/explicit/solver.hpp"
