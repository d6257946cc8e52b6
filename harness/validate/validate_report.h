// The printout of `raycoh validate` (also written as <out>.md): per paper column Table 1 (the paper's MRay/s and
// ratio beside ours: modeled, or measured with its 95% interval), Table 3 on Sibenik, then the goals.
#pragma once

#include <string>
#include <vector>

#include "records/validate_row.h"

namespace raycoh {

std::string validate_report(const std::string& order, int width, int height, const std::vector<ValidateRow>& rows);

}  // namespace raycoh
