// libfacetool (facetool::facetool): the libraries above the compute core in one shared library;
// its code is theirs (linked whole), this file only gives the target a source of its own.
namespace facetool {
const char* api_library_name() { return "libfacetool"; }
}  // namespace facetool
