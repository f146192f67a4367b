#include "emrm/scenario/statistics.hpp"
