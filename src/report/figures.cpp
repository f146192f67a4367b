#include "emrm/report/figures.hpp"
