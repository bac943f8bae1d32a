#include "util/json_int.h"

#include <gtest/gtest.h>

namespace brdfshot {

TEST(JsonInt, AcceptsIntegersInRangeOnly) {
  const nlohmann::json j = nlohmann::json::parse(
      R"({"w": 640, "neg": -5, "big": 6444444444444444444444444444444444444444, "frac": 2.5, "whole": 48.0,
          "huge": 18446744073709551615, "s": "640"})");
  EXPECT_EQ(JsonInt(j, "w", 1, 1 << 20, "f.json"), 640);
  EXPECT_EQ(JsonInt(j, "neg", -10, 10, "f.json"), -5);
  for (const char* key : {"neg", "big", "frac", "whole", "huge", "s"}) {
    try {
      JsonInt(j, key, 1, 1 << 20, "f.json");
      ADD_FAILURE() << key << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("f.json: '" + std::string(key) + "' must be an integer from 1 to 1048576"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(JsonInt(j, "missing", 0, 1, "f.json"), nlohmann::json::exception);
}

}  // namespace brdfshot
