#include "StripTree.h"
#include <gtest/gtest.h>
