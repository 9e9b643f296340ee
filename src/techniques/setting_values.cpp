// The one parser of technique settings (technique_descriptor.hpp).
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "farfield/core/text.hpp"
#include "farfield/core/assert.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

namespace {

bool in_choices(std::string_view choices, std::string_view value) {
  for (size_t begin = 0; begin <= choices.size();) {
    size_t end = choices.find('|', begin);
    if (end == std::string_view::npos) end = choices.size();
    if (choices.substr(begin, end - begin) == value) return true;
    begin = end + 1;
  }
  return false;
}

std::string choices_text(std::string_view choices) {
  std::string out(choices);
  for (char& c : out)
    if (c == '|') c = ',';
  return out;
}

}  // namespace

std::string describe_setting(const SettingSpec& s) {
  std::string rule;
  switch (s.type) {
    case SettingType::number:
    case SettingType::integer: {
      rule = s.type == SettingType::integer ? "whole number" : "number";
      const bool lo = std::isfinite(s.min), hi = std::isfinite(s.max);
      if (lo && hi) {
        rule += std::string(" in ") + (s.min_open ? "(" : "[") + number_text(s.min) + ", " +
                number_text(s.max) + (s.max_open ? ")" : "]");
      } else if (lo) {
        rule += std::string(s.min_open ? " > " : " >= ") + number_text(s.min);
      } else if (hi) {
        rule += std::string(s.max_open ? " < " : " <= ") + number_text(s.max);
      }
      break;
    }
    case SettingType::flag:
      rule = "0 or 1";
      break;
    case SettingType::choice:
      rule = "one of " + choices_text(s.choices);
      break;
    case SettingType::text:
      rule = "text";
      break;
  }
  if (!s.unit.empty()) rule += " " + std::string(s.unit);
  if (!s.default_value.empty()) rule += ", default " + std::string(s.default_value);
  return rule;
}

struct SettingsParser {
  // A value checked against its spec; the error names "--set NAME.KEY".
  static Result<void> check(std::string_view technique, const SettingSpec& s,
                            const std::string& text) {
    auto bad = [&](const char* what) {
      return make_error("--set ", std::string(technique), ".", std::string(s.key), "=", text, ": ",
                        what, " (", describe_setting(s), ")");
    };
    switch (s.type) {
      case SettingType::number:
      case SettingType::integer: {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v)) return bad("not a number");
        if (s.type == SettingType::integer && v != std::floor(v)) return bad("not a whole number");
        if (v < s.min || v > s.max || (s.min_open && v == s.min) || (s.max_open && v == s.max))
          return bad("out of range");
        return {};
      }
      case SettingType::flag:
        if (text != "0" && text != "1") return bad("must be 0 or 1");
        return {};
      case SettingType::choice:
        if (!in_choices(s.choices, text)) return bad("not one of the choices");
        return {};
      case SettingType::text:
        if (text.empty()) return bad("empty");
        return {};
    }
    return {};
  }

  static Result<SettingValues> parse(const TechniqueDescriptor& d, const TechniqueSettings& given) {
    SettingValues out;
    for (const SettingSpec& s : d.settings) {
      out.values_[std::string(s.key)] = std::string(s.default_value);
      out.given_[std::string(s.key)] = false;
    }
    for (const auto& [key, text] : given.for_technique(d.name)) {
      const SettingSpec* s = d.setting(key);
      if (s == nullptr) {
        std::string known;
        for (const SettingSpec& k : d.settings)
          known += (known.empty() ? "" : ", ") + std::string(k.key);
        return make_error(
            "--set ", std::string(d.name), ".", key, ": ", std::string(d.name),
            known.empty() ? " has no settings" : " has no such setting (known: " + known + ")");
      }
      if (auto ok = check(d.name, *s, text); !ok) return ok.error();
      out.values_[key] = text;
      out.given_[key] = true;
    }
    return out;
  }
};

const SettingSpec* TechniqueDescriptor::setting(std::string_view key) const {
  for (const SettingSpec& s : settings)
    if (s.key == key) return &s;
  return nullptr;
}

Result<SettingValues> parse_settings(const TechniqueDescriptor& descriptor,
                                     const TechniqueSettings& settings) {
  return SettingsParser::parse(descriptor, settings);
}

namespace {
const std::string& lookup(const std::map<std::string, std::string, std::less<>>& values,
                          std::string_view key) {
  const auto it = values.find(key);
  FF_ASSERT(it != values.end(), "no setting '%.*s' in the technique's descriptor", int(key.size()),
            key.data());
  return it->second;
}
}  // namespace

double SettingValues::number(std::string_view key) const {
  const std::string& text = lookup(values_, key);
  FF_ASSERT(!text.empty(), "setting '%.*s' has no value (a derived default)", int(key.size()),
            key.data());
  return std::strtod(text.c_str(), nullptr);
}

double SettingValues::number_or(std::string_view key, double otherwise) const {
  const std::string& text = lookup(values_, key);
  return text.empty() ? otherwise : std::strtod(text.c_str(), nullptr);
}

int SettingValues::integer(std::string_view key) const {
  return int(number(key));
}

bool SettingValues::flag(std::string_view key) const {
  return lookup(values_, key) == "1";
}

const std::string& SettingValues::text(std::string_view key) const {
  return lookup(values_, key);
}

bool SettingValues::given(std::string_view key) const {
  const auto it = given_.find(key);
  return it != given_.end() && it->second;
}

Result<void> TechniqueSettings::add(const std::string& assignment) {
  const size_t dot = assignment.find('.'), equals = assignment.find('=');
  if (dot == std::string::npos || equals == std::string::npos || dot == 0 || equals < dot + 2)
    return make_error("--set '", assignment, "': expected TECHNIQUE.KEY=VALUE");
  const std::string technique = assignment.substr(0, dot);
  if (auto found = find_technique(technique); !found)
    return make_error("--set ", assignment, ": ", found.error().message);
  values[assignment.substr(0, equals)] = assignment.substr(equals + 1);
  return {};
}

std::map<std::string, std::string> TechniqueSettings::for_technique(
    std::string_view technique) const {
  std::map<std::string, std::string> mine;
  const std::string prefix = std::string(technique) + ".";
  for (const auto& [key, value] : values)
    if (key.compare(0, prefix.size(), prefix) == 0) mine[key.substr(prefix.size())] = value;
  return mine;
}

}  // namespace farfield
