// Everything a generated model's implementation includes.
#pragma once

#include "mbrt/contacts.hpp"
#include "mbrt/dense_cholesky.hpp"
#include "mbrt/forces.hpp"
#include "mbrt/free_rotation.hpp"
#include "mbrt/joint_coordinates.hpp"
#include "mbrt/joints.hpp"
#include "mbrt/mass_properties.hpp"
#include "mbrt/model_api.hpp"
#include "mbrt/nonholonomic.hpp"
#include "mbrt/pivoted_inverse.hpp"
#include "mbrt/planar.hpp"
#include "mbrt/rotation.hpp"
