#include "StripTree.h"
