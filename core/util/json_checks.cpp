// first_duplicate_json_key: the keys of each open object collected while nlohmann::json parses.
#include "core/util/json_checks.h"

#include <nlohmann/json.hpp>
#include <set>
#include <vector>

namespace facetool {

std::string first_duplicate_json_key(const std::string& text) {
  std::vector<std::set<std::string>> keys_of_open_objects;
  std::string duplicate;
  const nlohmann::json::parser_callback_t track_keys =
      [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        if (event == nlohmann::json::parse_event_t::object_start)
          keys_of_open_objects.emplace_back();
        if (event == nlohmann::json::parse_event_t::object_end && !keys_of_open_objects.empty())
          keys_of_open_objects.pop_back();
        if (event == nlohmann::json::parse_event_t::key && !keys_of_open_objects.empty() &&
            !keys_of_open_objects.back().insert(parsed.get<std::string>()).second &&
            duplicate.empty())
          duplicate = parsed.get<std::string>();
        return true;
      };
  const nlohmann::json ignored = nlohmann::json::parse(text, track_keys, false);
  (void)ignored;
  return duplicate;
}

}  // namespace facetool
