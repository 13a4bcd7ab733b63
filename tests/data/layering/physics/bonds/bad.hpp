#pragma once
// A bond law may not know the World: the layering check must refuse this file.
#include "physics/dem/world.hpp"
