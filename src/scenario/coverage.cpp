#include "emrm/scenario/coverage.hpp"
