// Everything in neurov's C++ library.
#pragma once

#include "neurov/integrator.hpp"
#include "neurov/kinematics.hpp"
#include "neurov/status.hpp"
#include "neurov/types.hpp"
#include "neurov/validation.hpp"
#include "neurov/vehicle.hpp"
#include "neurov/version.hpp"
