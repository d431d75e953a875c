#include "Model.h"
#include <gtest/gtest.h>
