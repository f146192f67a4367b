#include "emrm/scenario/plan.hpp"
