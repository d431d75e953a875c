#include "DistanceField.h"
