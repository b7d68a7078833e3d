// Point2: a 2D point in pixel coordinates (x right, y down; pixel (i, j)'s centre at (i, j)).
#pragma once

namespace facetool {

struct Point2 {
  double x = 0, y = 0;
};

}  // namespace facetool
