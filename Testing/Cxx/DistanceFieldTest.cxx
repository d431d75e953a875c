#include "DistanceField.h"
#include <gtest/gtest.h>
