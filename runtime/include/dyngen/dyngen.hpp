// The dyngen runtime: spatial algebra, models, and the algorithms (RNEA, CRBA, ABA, ...),
// templated on the scalar type.
#pragma once

#include "dyngen/aba.hpp"
#include "dyngen/aba_derivatives.hpp"
#include "dyngen/algorithms.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/frames.hpp"
#include "dyngen/kinematics.hpp"
#include "dyngen/model.hpp"
#include "dyngen/minv.hpp"
#include "dyngen/model_builder.hpp"
#include "dyngen/regressor.hpp"
#include "dyngen/rnea.hpp"
#include "dyngen/rnea_derivatives.hpp"
#include "dyngen/workspace.hpp"
