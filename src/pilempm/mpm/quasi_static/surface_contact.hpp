#pragma once
// The penalty contact law of the quasi-static solver lives in mpm/surface_contact.hpp, shared with
// the explicit solver's surface contact; the quasi-static names refer to it.
#include "pilempm/mpm/surface_contact.hpp"

namespace pilempm::mpm::quasi_static {

using mpm::ContactHistory;
using mpm::ContactSettings;
using mpm::penalty_contact;
using mpm::PointContact;

}  // namespace pilempm::mpm::quasi_static
