// What a hostile or careless client sent, each refused at submission with INVALID_ARGUMENT naming the
// field (the daemon's run manager, in this process), and the CLI's input files: a table of the findings
// of a review of the daemon as a network service, each now refused or handled as it should be.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <fstream>

#include "core/scenario/run_builder.hpp"
#include "server/run_manager.hpp"
#include "tests/service/service_harness.hpp"

namespace kessler {
namespace {

using server::ServiceError;

struct HostileFinding {
  const char* what;
  std::string scenario_text;  // YAML, or empty for `message`
  v1::Scenario message;
  const char* path;          // the field named
  const char* message_part;  // a part of the message
};

const char* const kBase = "dt_s: 10\nduration_days: 0.01\npopulation:\n  synthetic:\n    objects: 100\n";

v1::Scenario base_message() {
  v1::Scenario s;
  if (parse_scenario(kBase, s)) throw std::logic_error("base scenario");
  return s;
}

std::vector<HostileFinding> hostile_findings() {
  std::vector<HostileFinding> out;
  auto text = [&](const char* what, std::string yaml, const char* path, const char* part) {
    out.push_back({what, std::move(yaml), {}, path, part});
  };
  auto message = [&](const char* what, v1::Scenario s, const char* path, const char* part) {
    out.push_back({what, "", std::move(s), path, part});
  };
  text("a year of steps", "dt_s: 1000\nduration_days: 3.4e6\npopulation:\n  synthetic:\n    objects: 100\n",
       "duration_days", "--max-run-steps");
  text("ten million objects",
       "dt_s: 10\nduration_days: 1\npopulation:\n  synthetic:\n    objects: 10000000\n", "population",
       "--max-run-objects");
  text("a cost of years", "dt_s: 10\nduration_days: 7305\npopulation:\n  synthetic:\n    objects: 1000000\n",
       "duration_days", "--max-run-object-steps");
  text("screening 5000 km", std::string(kBase) + "conjunctions:\n  screening_distance_km: 5000\n",
       "conjunctions.screening_distance_km", "--max-screening-km");
  text("screening 30000 km (failed at run start)",
       std::string(kBase) + "conjunctions:\n  screening_distance_km: 30000\n",
       "conjunctions.screening_distance_km", "domain");
  {
    v1::Scenario s = base_message();
    s.mutable_population()->mutable_synthetic()->set_max_altitude_km(std::numeric_limits<double>::infinity());
    message("max_altitude_km inf (failed at run start)", s, "population.synthetic.max_altitude_km",
            "must be a finite number");  // refused with every non-finite number of a request
  }
  {
    v1::Scenario s = base_message();
    s.set_propagator(static_cast<v1::Propagator>(99));
    message("an unknown enum number", s, "propagator", "unknown value 99");
  }
  {
    v1::Scenario s = base_message();
    s.mutable_conjunctions()->set_narrow_phase(static_cast<v1::NarrowPhase>(-4));
    message("an unknown nested enum number", s, "conjunctions.narrow_phase", "unknown value -4");
  }
  text("a duplicate key",
       "dt_s: 10\ndt_s: 20\nduration_days: 0.01\npopulation:\n  synthetic:\n    objects: 100\n", "dt_s",
       "is given twice");
  text("a key in both spellings", std::string(kBase) + "dtS: 2\n", "dtS", "is given twice");
  text("a second YAML document", std::string(kBase) + "---\ndt_s: 20\n", "", "2 YAML documents");
  text("a hyperbolic state",
       "population:\n  state_table: \"1,2022-01-01T00:00:00Z,7000000,0,0,0,12000,0,0.5,,\\n\"\n"
       "  rules:\n    strict: true\nstart_epoch: \"2022-01-01T00:00:00Z\"\nduration_days: 0.01\n",
       "population", "escape speed");
  text("a radius of 1e30 m",
       "population:\n  state_table: \"1,2022-01-01T00:00:00Z,7000000,0,0,0,7546,0,1e30,,\\n\"\n"
       "  rules:\n    strict: true\nstart_epoch: \"2022-01-01T00:00:00Z\"\nduration_days: 0.01\n",
       "population", "radius_m must be at most 1000 m");
  return out;
}

class HostileInput : public ::testing::Test {
 protected:
  void SetUp() override {
    server::ManagerOptions options;
    options.db_path = dir_.path() + "/k.db";
    manager_ = std::make_unique<server::RunManager>(options);
  }
  TempDir dir_;
  std::unique_ptr<server::RunManager> manager_;
};

TEST_F(HostileInput, EveryFindingIsRefusedAtSubmissionNamingTheField) {
  for (const HostileFinding& f : hostile_findings()) {
    SCOPED_TRACE(f.what);
    v1::SubmitRunRequest request;
    if (f.scenario_text.empty())
      *request.mutable_scenario() = f.message;
    else
      request.set_scenario_text(f.scenario_text);
    try {
      manager_->submit(request);
      ADD_FAILURE() << "accepted";
    } catch (const ServiceError& e) {
      EXPECT_EQ(e.code, ServiceError::Code::kInvalidArgument) << e.what();
      EXPECT_EQ(e.field_path.rfind(f.path, 0), 0u) << e.field_path << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find(f.message_part), std::string::npos) << e.what();
    }
  }
  // Nothing was stored, and the daemon takes a sound scenario.
  EXPECT_TRUE(manager_->list(v1::ListRunsRequest()).runs().empty());
  v1::SubmitRunRequest sound;
  sound.set_scenario_text(kBase);
  EXPECT_GT(manager_->submit(sound).id(), 0);
}

TEST_F(HostileInput, ErrorsQuoteOnlyAShortPrefixOfABadValue) {
  const std::string huge(1 << 20, 'z');
  for (const std::string& text :
       {std::string(kBase) + "propagator: " + huge + "\n", std::string(kBase) + huge + ": 1\n",
        std::string(kBase) + "dt_s: " + huge + "\n"}) {
    v1::SubmitRunRequest request;
    request.set_scenario_text(text);
    try {
      manager_->submit(request);
      ADD_FAILURE() << "accepted";
    } catch (const ServiceError& e) {
      EXPECT_LT(std::string(e.what()).size(), 1000u) << std::string(e.what()).substr(0, 200);
      EXPECT_LT(e.field_path.size(), 200u);
    }
  }
}

TEST_F(HostileInput, LimitsComeFromTheDaemonsFlags) {
  server::ManagerOptions options;
  options.db_path = dir_.path() + "/strict.db";
  options.limits.max_objects = 50;
  server::RunManager strict(options);
  v1::SubmitRunRequest request;
  request.set_scenario_text(kBase);  // 100 objects
  try {
    strict.submit(request);
    ADD_FAILURE() << "accepted";
  } catch (const ServiceError& e) {
    EXPECT_NE(std::string(e.what()).find("100 objects, above this daemon's limit of 50"), std::string::npos)
        << e.what();
  }
}

// The CLI's input files: a FIFO does not hang, /dev/zero does not exhaust memory, a binary file and a
// directory are named for what they are; all exit 2 before any daemon is asked.
TEST(HostileCliInput, OddInputFilesAreRefusedWithExit2AndAClearReason) {
  TempDir dir;
  const std::string fifo = dir.path() + "/fifo.yaml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string binary = dir.path() + "/binary.yaml";
  {
    std::ofstream out(binary, std::ios::binary);
    const char bytes[] = {'d', 't', '_', 's', ':', ' ', '\x00', '\xff', '\xfe', '\x01'};
    out.write(bytes, sizeof bytes);
  }
  const std::string latin1 = dir.path() + "/latin1.yaml";
  test::write_text(latin1, std::string("name: caf\xe9\n") + kBase);
  struct Case {
    std::string file, reason;
  };
  for (const Case& c :
       {Case{fifo, "is a FIFO, not a file"}, Case{"/dev/zero", "is a character device, not a file"},
        Case{binary, "is not a text file (a NUL byte at offset 6)"},
        Case{latin1, "is not a text file (not UTF-8 at offset 9)"}, Case{dir.path(), "is a directory"}}) {
    SCOPED_TRACE(c.file);
    const auto start = std::chrono::steady_clock::now();
    test::CliResult r = test::cli(dir, "submit " + c.file + " --server 127.0.0.1:1");
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(c.reason), std::string::npos) << r.err;
    test::CliResult local = test::cli(dir, "run " + c.file + " --local");
    EXPECT_EQ(local.exit_code, 2) << local.err;
    EXPECT_NE(local.err.find(c.reason), std::string::npos) << local.err;
  }
}

TEST(HostileCliInput, ANegativeRetryIsRefusedAndZeroThreadsMeansAllCores) {
  TempDir dir;
  test::write_text(dir.path() + "/s.yaml", kBase);
  test::CliResult retry = test::cli(dir, "watch 1 --retry-s -5 --server 127.0.0.1:1");
  EXPECT_EQ(retry.exit_code, 2);
  EXPECT_NE(retry.err.find("--retry-s: must be a number of seconds from 0 to 1e9, got -5"), std::string::npos)
      << retry.err;
  test::CliResult all_cores =
      test::cli(dir, "run " + dir.path() + "/s.yaml --local --threads 0 --output json");
  EXPECT_EQ(all_cores.exit_code, 0) << all_cores.err;
  test::CliResult one = test::cli(dir, "run " + dir.path() + "/s.yaml --local --threads 1 --output json");
  auto digest = [](const std::string& line) {
    const auto at = line.find("\"events_digest\"");
    return at == std::string::npos ? std::string("none") : line.substr(at, 84);
  };
  EXPECT_NE(digest(all_cores.last_line()), "none") << all_cores.out;
  EXPECT_EQ(digest(all_cores.last_line()), digest(one.last_line()));  // the same run on any thread count
}

}  // namespace
}  // namespace kessler
