// Parsing the landmark fit's options.
#include "apps/facetool/fit/fit_options.h"

#include <sstream>

namespace po = boost::program_options;

namespace facetool {

void add_fit_options(po::options_description& options) {
  const FitSettings d;
  std::ostringstream smoothing;  // shown as 0.025, not with the double's every digit
  smoothing << PhotoFitOptions::kDefaultNormalSmoothing;
  options.add_options()
      ("camera", po::value<std::string>()->default_value("perspective")->value_name("perspective|orthographic"),
       "camera model of the fit: a pinhole with the field of view --fov, or scaled orthographic (docs/fit.md: measured choice)")
      ("fov", po::value<double>()->default_value(d.fov_deg), "--camera perspective: horizontal field of view over the photo's width, degrees")
      ("jaw", po::value<std::string>()->default_value("down-weighted")->value_name("down-weighted|contour"),
       "jaw-line landmarks: re-chosen silhouette vertices (contour), or fixed vertices with a lower weight")
      ("jaw-weight", po::value<double>()->default_value(d.jaw_weight),
       "--jaw down-weighted: weight of the 17 jaw-line landmarks (the others 1)")
      ("identity-prior", po::value<double>()->default_value(d.identity_prior), "weight of the N(0, 1) prior on identity weights")
      ("expression-prior", po::value<double>()->default_value(d.expression_prior), "weight of the sparsity prior on expression weights")
      ("no-expressions", "fit identity and pose only (expression weights 0)")
      ("smooth-normals", po::value<double>()->default_value(PhotoFitOptions::kDefaultNormalSmoothing, smoothing.str()),
       "standard deviation of the Gaussian that smooths the fitted normals, as a fraction of the eye distance (0: the "
       "mesh's own normals; docs/fit.md, \"Smoothed normals\")")
      ("directions", po::value<int>()->default_value(872), "visibility ray directions per pixel (the paper's 872)")
      ("no-visibility", "skip the visibility rays (visibility.exr is 0)");
}

std::vector<OptionRange> fit_option_ranges() {
  return {{"fov", 1, 120}, {"jaw-weight", 0, 10}, {"identity-prior", 0, 1e6}, {"expression-prior", 0, 1e6}, {"smooth-normals", 0, 1}, {"directions", 1, 100000}};
}

PhotoFitOptions fit_options_from(const po::variables_map& values) {
  PhotoFitOptions o;
  const std::string camera = values["camera"].as<std::string>();
  if (camera == "orthographic") o.fit.camera = FitCamera::kScaledOrthographic;
  else if (camera == "perspective") o.fit.camera = FitCamera::kPerspective;
  else throw UsageError("--camera must be orthographic or perspective; got '" + camera + "'");
  const std::string jaw = values["jaw"].as<std::string>();
  if (jaw == "contour") o.fit.jaw = JawHandling::kContour;
  else if (jaw == "down-weighted") o.fit.jaw = JawHandling::kDownWeighted;
  else throw UsageError("--jaw must be contour or down-weighted; got '" + jaw + "'");
  o.fit.fov_deg = values["fov"].as<double>();
  o.fit.jaw_weight = values["jaw-weight"].as<double>();
  o.fit.identity_prior = values["identity-prior"].as<double>();
  o.fit.expression_prior = values["expression-prior"].as<double>();
  o.fit.fit_expressions = !values.count("no-expressions");
  o.render.normal_smoothing = values["smooth-normals"].as<double>();
  o.direction_count = values["directions"].as<int>();
  o.render.visibility = !values.count("no-visibility");
  return o;
}

}  // namespace facetool
