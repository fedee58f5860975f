// Config files of the verbs (tools/cli_config): the YAML reader's items and errors, and the whole
// round through CLI11 (file values, command-line overrides, required options, --write-config).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_config.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::cli {
namespace {

namespace fs = std::filesystem;

/// A root app with `eval cells`, options of every kind bound to the fields.
struct TestCli {
  CLI::App app{"test"};
  CLI::App* cells = nullptr;
  std::string log, truth, units = "m";
  int tolerance = 2;
  double scale = 1.0;
  std::uint64_t seed = 1;
  bool quiet = false, vectorize = true;
  std::vector<double> weights;
  bool ran = false;

  TestCli() {
    CLI::App* eval = app.add_subcommand("eval", "scores");
    eval->require_subcommand(1);
    cells = eval->add_subcommand("cells", "cell scores");
    cells->add_option("log", log, "a log");
    cells->add_option("--truth", truth, "true plan")->required();
    cells->add_option("--units", units, "units\nof the plan")->capture_default_str();
    cells->add_option("--tolerance", tolerance, "tolerance [cells]");
    cells->add_option("--scale", scale, "scale");
    cells->add_option("--seed", seed, "seed");
    cells->add_option("--weights", weights, "weights");
    cells->add_flag("-q,--quiet", quiet, "quiet");
    cells->add_flag("!--no-vector", vectorize, "no vectors");
    cells->callback([this] { ran = true; });
    addConfigOptions(app);
  }

  /// Parses `args` (after the program name); returns --write-config's output, empty when none.
  std::string parse(std::vector<std::string> args) {
    args.insert(args.begin(), "glassmap");
    std::vector<const char*> argv;
    for (const auto& a : args) argv.push_back(a.c_str());
    testing::internal::CaptureStdout();
    try {
      app.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::Success&) {
    } catch (...) {
      testing::internal::GetCapturedStdout();
      throw;
    }
    return testing::internal::GetCapturedStdout();
  }
};

std::vector<CLI::ConfigItem> read(const std::string& yaml) {
  TestCli cli;
  std::istringstream in(yaml);
  return readVerbConfig(in, *cli.cells, "f.yaml");
}

/// The line and message of the Error reading `yaml` throws.
std::pair<std::size_t, std::string> readError(const std::string& yaml) {
  try {
    read(yaml);
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "f.yaml");
    return {e.line(), e.what()};
  }
  ADD_FAILURE() << "no error for:\n" << yaml;
  return {0, {}};
}

fs::path tempFile(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("glassmap_cli_config_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

TEST(CliConfig, ReadsKeysOfEveryKind) {
  const auto items = read(
      "# a comment\n"
      "log: run.clf\n"
      "truth: 'plan with spaces.gpkg'\n"
      "tolerance: 3\n"
      "scale: 0.5\n"
      "seed: 42\n"
      "weights: [1, 2.5]\n"
      "quiet: true\n"
      "no-vector: false\n");
  ASSERT_EQ(items.size(), 8u);
  for (const auto& item : items) EXPECT_EQ(item.parents, (std::vector<std::string>{"eval", "cells"}));
  EXPECT_EQ(items[0].name, "log");
  EXPECT_EQ(items[0].inputs, std::vector<std::string>{"run.clf"});
  EXPECT_EQ(items[1].inputs, std::vector<std::string>{"plan with spaces.gpkg"});
  EXPECT_EQ(items[5].name, "weights");
  EXPECT_EQ(items[5].inputs, (std::vector<std::string>{"1", "2.5"}));
  EXPECT_EQ(items[6].inputs, std::vector<std::string>{"true"});
  EXPECT_TRUE(read("").empty());
  EXPECT_TRUE(read("# only comments\n").empty());
}

TEST(CliConfig, ErrorsNameFileLineAndKey) {
  auto [line, what] = readError("truth: a\ntolerence: 3\n");
  EXPECT_EQ(line, 2u);
  EXPECT_NE(what.find("f.yaml:2: tolerence: unknown key"), std::string::npos) << what;
  EXPECT_NE(what.find("tolerance"), std::string::npos) << what;  // lists the keys

  std::tie(line, what) = readError("truth: a\n\ntolerance: 2.5\n");
  EXPECT_EQ(line, 3u);
  EXPECT_NE(what.find("expected an integer, got '2.5'"), std::string::npos) << what;
  std::tie(line, what) = readError("scale: fast\n");
  EXPECT_NE(what.find("expected a number"), std::string::npos) << what;
  std::tie(line, what) = readError("seed: -1\n");
  EXPECT_NE(what.find("non-negative integer"), std::string::npos) << what;
  std::tie(line, what) = readError("quiet: maybe\n");
  EXPECT_NE(what.find("true or false"), std::string::npos) << what;
  std::tie(line, what) = readError("weights: [1, x]\n");
  EXPECT_NE(what.find("expected a number, got 'x'"), std::string::npos) << what;
  std::tie(line, what) = readError("truth: a\nscale: [1, 2]\n");
  EXPECT_EQ(line, 2u);
  EXPECT_NE(what.find("got a list"), std::string::npos) << what;
  std::tie(line, what) = readError("truth:\n");
  EXPECT_NE(what.find("no value"), std::string::npos) << what;
  std::tie(line, what) = readError("q: true\nquiet: false\n");
  EXPECT_EQ(line, 2u);
  EXPECT_NE(what.find("given twice"), std::string::npos) << what;
  std::tie(line, what) = readError("truth: a\nconfig: other.yaml\n");
  EXPECT_NE(what.find("cannot be set in a config file"), std::string::npos) << what;
  std::tie(line, what) = readError("help: true\n");
  EXPECT_NE(what.find("unknown key"), std::string::npos) << what;
  std::tie(line, what) = readError("- a\n- b\n");
  EXPECT_NE(what.find("expected a mapping"), std::string::npos) << what;
  std::tie(line, what) = readError("truth: a\nscale: [1, 2\n");
  EXPECT_GE(line, 2u);
  EXPECT_NE(what.find("YAML syntax"), std::string::npos) << what;
}

TEST(CliConfig, FileThenCommandLine) {
  const fs::path file = tempFile("run.yaml", "log: a.clf\ntruth: plan.gpkg\ntolerance: 4\nscale: 2\nno-vector: true\n");
  TestCli cli;
  EXPECT_EQ(cli.parse({"eval", "cells", "-c", file.string(), "--scale", "3", "-q"}), "");
  EXPECT_TRUE(cli.ran);
  EXPECT_EQ(cli.log, "a.clf");
  EXPECT_EQ(cli.truth, "plan.gpkg");  // a required option given only in the file
  EXPECT_EQ(cli.tolerance, 4);
  EXPECT_DOUBLE_EQ(cli.scale, 3.0);  // the command line wins
  EXPECT_TRUE(cli.quiet);
  EXPECT_FALSE(cli.vectorize);

  TestCli missing;
  EXPECT_THROW(missing.parse({"eval", "cells", "-c", (file.parent_path() / "none.yaml").string()}), CLI::FileError);
  TestCli bad;
  const fs::path bad_file = tempFile("bad.yaml", "truth: a\nscale: x\n");
  try {
    bad.parse({"eval", "cells", "--config", bad_file.string()});
    ADD_FAILURE() << "bad config accepted";
  } catch (const CLI::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:2: scale:"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(bad.ran);
  TestCli required;
  EXPECT_THROW(required.parse({"eval", "cells", "log.clf"}), CLI::RequiredError);
  fs::remove_all(file.parent_path());
}

TEST(CliConfig, WriteConfigRepeatsTheRun) {
  TestCli direct;
  const std::string written = direct.parse({"eval", "cells", "x.clf", "--truth", "t: 1.gpkg", "--weights", "1",
                                            "--weights", "2", "--no-vector", "--tolerance", "5", "--write-config"});
  EXPECT_FALSE(direct.ran);
  EXPECT_NE(written.find("# glassmap eval cells:"), std::string::npos) << written;
  EXPECT_NE(written.find("\nlog: x.clf\n"), std::string::npos) << written;
  EXPECT_NE(written.find("\nno-vector: true\n"), std::string::npos) << written;
  EXPECT_NE(written.find("\nweights:\n  - 1\n  - 2\n"), std::string::npos) << written;
  EXPECT_NE(written.find("\n# units\n# of the plan\n# units: m\n"), std::string::npos) << written;  // default
  EXPECT_NE(written.find("\n# quiet: false\n"), std::string::npos) << written;
  EXPECT_EQ(written.find("write-config:"), std::string::npos) << written;

  const fs::path file = tempFile("written.yaml", written);
  TestCli again;
  EXPECT_EQ(again.parse({"eval", "cells", "-c", file.string(), "--write-config"}), written);
  TestCli run;
  run.parse({"eval", "cells", "-c", file.string()});
  EXPECT_TRUE(run.ran);
  EXPECT_EQ(run.truth, "t: 1.gpkg");
  EXPECT_EQ(run.weights, (std::vector<double>{1, 2}));
  EXPECT_FALSE(run.vectorize);
  EXPECT_EQ(run.tolerance, 5);
  EXPECT_EQ(run.units, "m");
  fs::remove_all(file.parent_path());
}

}  // namespace
}  // namespace glassmap::cli
