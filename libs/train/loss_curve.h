// The loss-curve picture kept current in a run folder: total training loss per step, log scale.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace facetool {

// Draws the (step, loss) points (loss > 0) as a line on a log10 axis, with grid lines at each
// power of ten, into a width x height PNG written atomically. Fewer than two points: a blank plot.
void write_loss_curve(const std::string& path, const std::vector<std::pair<double, double>>& points,
                      int width = 640, int height = 360);

}  // namespace facetool
