// Invariants of the language index over every corpus file and example (filled in below).
#include "frontend/index/index.h"

#include <gtest/gtest.h>
