// The method table answers what other code asks of a method by name (method_table.hpp).
#include "methods/method_table.hpp"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace imx {
namespace {

TEST(MethodsTable, NamesEveryAvailableMethodOnce) {
  const std::vector<std::string> names = available_methods();
  ASSERT_EQ(names.size(), method_table().size());
  for (size_t i = 0; i < names.size(); ++i) {
    const MethodInfo* m = find_method(names[i]);
    ASSERT_NE(m, nullptr) << names[i];
    EXPECT_EQ(m, &method_table()[i]);
    EXPECT_EQ(m->default_spp, default_spp(names[i]));
    EXPECT_GE(m->default_spp, 1);
  }
  EXPECT_EQ(find_method(""), nullptr);
  EXPECT_EQ(find_method("zslab-"), nullptr);
  EXPECT_EQ(find_method("ZSLAB"), nullptr);
}

TEST(MethodsTable, Properties) {
  std::vector<std::string> csg, kept, distributable;
  for (const MethodInfo& m : method_table()) {
    if (m.renders_csg) csg.push_back(m.name);
    if (m.keeps_stages != KeptStages::none) kept.push_back(m.name);
    if (m.distributable) distributable.push_back(m.name);
  }
  EXPECT_EQ(csg, (std::vector<std::string>{"reference", "csg"}));
  EXPECT_EQ(kept, (std::vector<std::string>{"zslab", "zslab-hybrid"}));
  EXPECT_EQ(distributable, (std::vector<std::string>{"zslab", "zslab-hybrid"}));
  EXPECT_EQ(find_method("zslab")->keeps_stages, KeptStages::zslab);
  EXPECT_EQ(find_method("zslab-hybrid")->keeps_stages, KeptStages::zslab_hybrid);
}

}  // namespace
}  // namespace imx
