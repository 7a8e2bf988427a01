// Everything in neurov's C++ library.
#pragma once

#include "neurov/config.hpp"
#include "neurov/desired_state.hpp"
#include "neurov/integrator.hpp"
#include "neurov/kinematics.hpp"
#include "neurov/linear_adaptive_controller.hpp"
#include "neurov/nn_controller.hpp"
#include "neurov/pd_controller.hpp"
#include "neurov/rbf_network.hpp"
#include "neurov/reference_model.hpp"
#include "neurov/regressor.hpp"
#include "neurov/status.hpp"
#include "neurov/tracking_error.hpp"
#include "neurov/types.hpp"
#include "neurov/validation.hpp"
#include "neurov/vehicle.hpp"
#include "neurov/version.hpp"
