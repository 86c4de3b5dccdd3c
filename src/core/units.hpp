#pragma once
// Length units of inputs (include/poreshell/geometry.hpp). Every output is in millimetres.

#include "poreshell/geometry.hpp"
