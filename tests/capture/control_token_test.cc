// The control token from --token, --token-file or MOCAPLABEL_TOKEN (kept out of `ps`).
#include <gtest/gtest.h>

#include <fstream>

#include "capture/daemon/control_token.h"
#include "core/check.h"
#include "test_dirs.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

fs::path WriteFile(const fs::path& dir, const std::string& name, const std::string& content) {
  std::ofstream(dir / name) << content;
  return dir / name;
}

TEST(ControlToken, ComesFromTheFlagTheFileOrTheEnvironment) {
  const fs::path dir = testing::FreshCaptureDir("token");
  EXPECT_EQ(ResolveControlToken({}), "");
  EXPECT_EQ(ResolveControlToken({.flag_token = "s3cret"}), "s3cret");
  const fs::path file = WriteFile(dir, "token", "  from-file\n# a comment line is ignored\n");
  EXPECT_EQ(ResolveControlToken({.token_file = file}), "from-file");
  EXPECT_EQ(ResolveControlToken({.environment = "from-env\n"}), "from-env");
  // A flag wins over the environment, so a script can override an exported token.
  EXPECT_EQ(ResolveControlToken({.flag_token = "flag", .environment = "env"}), "flag");
  EXPECT_EQ(ResolveControlToken({.token_file = file, .environment = "env"}), "from-file");
}

TEST(ControlToken, RefusesAmbiguousOrUnusableTokens) {
  const fs::path dir = testing::FreshCaptureDir("token_bad");
  const fs::path file = WriteFile(dir, "token", "t\n");
  EXPECT_THROW(ResolveControlToken({.flag_token = "a", .token_file = file}), InputError);  // which one?
  EXPECT_THROW(ResolveControlToken({.token_file = dir / "missing"}), InputError);
  EXPECT_THROW(ResolveControlToken({.token_file = WriteFile(dir, "empty", "\n\n")}), InputError);
  EXPECT_THROW(ResolveControlToken({.token_file = WriteFile(dir, "spaces", "two words\n")}), InputError);
  EXPECT_THROW(ResolveControlToken({.environment = ""}), InputError);
  EXPECT_THROW(ResolveControlToken({.flag_token = "a\tb"}), InputError);
  try {
    ResolveControlToken({.token_file = dir / "missing"});
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
}

TEST(ControlToken, ReadsTheEnvironmentVariable) {
  ::setenv(kTokenEnvironmentVariable, "exported", 1);
  EXPECT_EQ(ResolveControlToken(TokenSourcesFromEnvironment("", "")), "exported");
  EXPECT_EQ(ResolveControlToken(TokenSourcesFromEnvironment("flag", "")), "flag");
  ::unsetenv(kTokenEnvironmentVariable);
  EXPECT_EQ(ResolveControlToken(TokenSourcesFromEnvironment("", "")), "");
}

}  // namespace
}  // namespace mocap::capture
