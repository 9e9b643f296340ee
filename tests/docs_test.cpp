// The docs say what the code does: each technique's settings table in docs/techniques/ is the
// one its descriptor makes (scripts/settings_tables.py rewrites them).
#include <gtest/gtest.h>

#include <filesystem>

#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

TEST(Docs, SettingsTablesMatchTheDescriptors) {
  const std::filesystem::path docs =
      std::filesystem::path(FARFIELD_SOURCE_DIR) / "docs" / "techniques";
  std::string all;
  for (const auto& entry : std::filesystem::directory_iterator(docs))
    if (entry.path().extension() == ".md") all += test::read_file(entry.path().string());
  for (const TechniqueDescriptor* d : technique_descriptors()) {
    const std::string open = "<!-- settings " + std::string(d->name) + " -->\n";
    const size_t at = all.find(open);
    ASSERT_NE(at, std::string::npos) << d->name << " has no settings table in docs/techniques";
    const size_t end = all.find("<!-- /settings -->", at);
    ASSERT_NE(end, std::string::npos);
    EXPECT_EQ(all.substr(at + open.size(), end - at - open.size()), settings_table_markdown(*d))
        << d->name << ": run scripts/settings_tables.py build/farfield";
  }
}

}  // namespace
}  // namespace farfield
