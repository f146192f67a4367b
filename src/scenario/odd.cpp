#include "emrm/scenario/odd.hpp"
