// In a real browser: headless Chromium opens the report file that `kessler report` wrote and the
// dashboard of a kesslerd started here on loopback. Every figure renders with the marks its data
// holds, the page logs no console errors, and a screenshot is not blank. Skipped, saying so, where
// Chromium is absent. Also the report's refusals (unknown run, unwritable path) and a partial report.
#include <gtest/gtest.h>
#include <zlib.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <thread>

#include "tests/service/service_harness.hpp"
#include "tests/web/crossings.hpp"
// httplib after the server's headers (resolv.h's _res macro breaks Eigen's headers).
#include <httplib.h>
#include <nlohmann/json.hpp>

namespace kessler {
namespace {

using nlohmann::json;
using test::cli;

std::string find_chromium() {
  if (const char* env = std::getenv("KESSLER_CHROMIUM")) return env;
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"})
    for (const char* dir : {"/usr/bin/", "/usr/local/bin/", "/snap/bin/"})
      if (std::filesystem::exists(std::string(dir) + name)) return std::string(dir) + name;
  return "";
}

// Runs headless Chromium on `url` with `mode` (--dump-dom or --screenshot=PATH); returns stdout.
std::string chromium(const TempDir& dir, const std::string& mode, const std::string& url) {
  const std::string out = dir.path() + "/chromium.out";
  const std::string cmd = find_chromium() + " --headless --no-sandbox --disable-gpu --no-first-run " +
                          "--user-data-dir=" + dir.path() + "/profile --virtual-time-budget=15000 " +
                          "--window-size=1200,2600 " + mode + " '" + url + "' > " + out + " 2> " + out +
                          ".err";
  std::system(cmd.c_str());
  return test::read_text(out);
}

// What the page's render script recorded (web/figure_page.hpp).
json render_results(const std::string& dom) {
  const std::string open = "<pre id=\"kessler-render-results\" hidden=\"\">";
  const auto start = dom.find(open);
  if (start == std::string::npos) return nullptr;
  const auto end = dom.find("</pre>", start);
  std::string text = dom.substr(start + open.size(), end - start - open.size());
  for (auto [from, to] :
       {std::pair<std::string, std::string>{"&quot;", "\""}, {"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}})
    for (std::size_t p; (p = text.find(from)) != std::string::npos;) text.replace(p, from.size(), to);
  return json::parse(text);
}

// The marks the figures' data should give: a line per series, a point per kappa, a bar per phase, a
// rule per marker; the snapshot figures draw marks.
void expect_marks(const json& results, const json& figures) {
  ASSERT_TRUE(results.is_object());
  EXPECT_TRUE(results["done"].get<bool>());
  EXPECT_TRUE(results["errors"].empty()) << results["errors"].dump();
  std::map<std::string, json> spec;
  for (const json& f : figures) spec[f["id"]] = f["spec"];
  // The four figures of the run's stats and events, then four of its snapshots and conjunctions.
  ASSERT_EQ(results["figures"].size(), 8u) << results.dump();
  ASSERT_EQ(figures.size(), 8u);
  for (const char* id :
       {"population-distributions", "conjunction-sizes", "conjunction-orbits", "spatial-density"})
    EXPECT_FALSE(results["figures"][id].empty()) << id << " drew no marks: " << results.dump();
  EXPECT_EQ(results["figures"]["conjunctions-over-time"], json({{"line", 4}}));
  EXPECT_EQ(results["figures"]["conjunctions-vs-kappa"], json({{"line", 1}, {"symbol", 10}}));
  EXPECT_EQ(results["figures"]["runtime-breakdown"], json({{"rect", 6}}));
  std::set<std::string> types;
  for (const json& row : spec["objects-by-type"]["layer"][0]["data"]["values"]) types.insert(row["type"]);
  EXPECT_GE(types.size(), 5u);
  EXPECT_EQ(
      results["figures"]["objects-by-type"],
      json({{"line", types.size()}, {"rule", spec["objects-by-type"]["layer"][1]["data"]["values"].size()}}));
}

// A PNG's pixels differ: more than 2 % of them from the top-left one. Decodes 8-bit RGB(A) PNGs.
double share_not_background(const std::string& png) {
  if (png.size() < 33 || png.compare(1, 3, "PNG") != 0) return -1;
  auto be32 = [&](std::size_t at) {
    return (std::uint32_t(std::uint8_t(png[at])) << 24) | (std::uint32_t(std::uint8_t(png[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(png[at + 2])) << 8) | std::uint32_t(std::uint8_t(png[at + 3]));
  };
  const std::uint32_t width = be32(16), height = be32(20);
  const int depth = png[24], color = png[25];
  if (depth != 8 || (color != 2 && color != 6)) return -1;
  const std::size_t bpp = color == 6 ? 4 : 3, stride = width * bpp;
  std::string idat;
  for (std::size_t at = 8; at + 8 <= png.size();) {
    const std::uint32_t length = be32(at);
    if (png.compare(at + 4, 4, "IDAT") == 0) idat += png.substr(at + 8, length);
    at += 12 + length;
  }
  std::vector<unsigned char> raw((stride + 1) * height);
  uLongf size = raw.size();
  if (uncompress(raw.data(), &size, reinterpret_cast<const Bytef*>(idat.data()), idat.size()) != Z_OK)
    return -1;
  std::vector<unsigned char> image(stride * height), prior(stride, 0);
  for (std::size_t y = 0; y < height; ++y) {
    const unsigned char filter = raw[y * (stride + 1)];
    unsigned char* row = &image[y * stride];
    const unsigned char* in = &raw[y * (stride + 1) + 1];
    for (std::size_t x = 0; x < stride; ++x) {
      const int a = x >= bpp ? row[x - bpp] : 0, b = prior[x], c = x >= bpp ? prior[x - bpp] : 0;
      int predicted = 0;
      if (filter == 1) predicted = a;
      if (filter == 2) predicted = b;
      if (filter == 3) predicted = (a + b) / 2;
      if (filter == 4) {
        const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
        predicted = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      row[x] = static_cast<unsigned char>(in[x] + predicted);
    }
    std::copy(row, row + stride, prior.begin());
  }
  std::size_t differing = 0;
  for (std::size_t p = 0; p < std::size_t(width) * height; ++p)
    if (std::memcmp(&image[p * bpp], &image[0], 3) != 0) ++differing;
  return static_cast<double>(differing) / (static_cast<double>(width) * height);
}

class Browser : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { shared_ = new Shared(); }
  static void TearDownTestSuite() {
    delete shared_;
    shared_ = nullptr;
  }
  struct Shared {
    Shared()
        : daemon(dir.path() + "/k.db",
                 {"--http", "127.0.0.1:0", "--http-port-file", dir.path() + "/http.port"}) {
      daemon.start();
      http_port = std::stoi(test::read_text(dir.path() + "/http.port"));
      test::write_text(dir.path() + "/crossings.yaml", test::crossings_scenario());
      submitted =
          cli(dir, "--server " + daemon.address() + " submit " + dir.path() + "/crossings.yaml --watch");
      report = cli(dir, "--server " + daemon.address() + " report 1 -o " + dir.path() + "/report.html");
      httplib::Client client("127.0.0.1", http_port);
      auto r = client.Get("/api/runs/1/figures");
      if (r) figures = json::parse(r->body)["figures"];
      // An ensemble of the same run (three seeds, the same passes), to its end.
      test::write_text(dir.path() + "/ensemble.yaml",
                       test::crossings_scenario() + "ensemble: {members: 3}\n");
      ensemble_submitted =
          cli(dir, "--server " + daemon.address() + " submit " + dir.path() + "/ensemble.yaml");
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
      while (std::chrono::steady_clock::now() < deadline) {
        auto e = client.Get("/api/ensembles/1");
        // uint64 fields are strings in protobuf's JSON.
        if (e && e->status == 200 && json::parse(e->body).value("finished", "") == "3") break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      auto f = client.Get("/api/ensembles/1/figures");
      if (f) ensemble_figures = json::parse(f->body)["figures"];
    }
    TempDir dir;
    test::Daemon daemon;
    int http_port = 0;
    test::CliResult submitted, report, ensemble_submitted;
    json figures, ensemble_figures;
  };
  void SetUp() override {
    if (find_chromium().empty())
      GTEST_SKIP()
          << "Chromium not found (KESSLER_CHROMIUM, or chromium on the PATH): the browser tests need "
             "it; deploy/install-deps.sh installs Debian's chromium";
    ASSERT_EQ(shared_->submitted.exit_code, 0) << shared_->submitted.err;
    ASSERT_EQ(shared_->report.exit_code, 0) << shared_->report.err;
  }
  static Shared* shared_;
};
Browser::Shared* Browser::shared_ = nullptr;

TEST_F(Browser, TheReportFileRendersEveryFigureOffline) {
  const std::string dom =
      chromium(shared_->dir, "--dump-dom", "file://" + shared_->dir.path() + "/report.html");
  expect_marks(render_results(dom), shared_->figures);
  // The report stands alone: no script or style from elsewhere.
  const std::string html = test::read_text(shared_->dir.path() + "/report.html");
  EXPECT_EQ(html.find("<script src="), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_NE(html.find("events digest"), std::string::npos);
  EXPECT_EQ(html.find("Partial"), std::string::npos);
}

TEST_F(Browser, TheDashboardsRunPageRendersEveryFigureAndTheConjunctions) {
  const std::string base = "http://127.0.0.1:" + std::to_string(shared_->http_port);
  const std::string dom = chromium(shared_->dir, "--dump-dom", base + "/runs/1");
  expect_marks(render_results(dom), shared_->figures);
  EXPECT_NE(dom.find("run 1 (web-crossings): succeeded"), std::string::npos);
  EXPECT_NE(dom.find("4 matching"),
            std::string::npos);  // the 4 passes at kappa <= 10, the collision one of them
  const std::string index = chromium(shared_->dir, "--dump-dom", base + "/");
  EXPECT_NE(index.find("<a href=\"/runs/1\">1</a>"), std::string::npos);
}

// The ensemble's page: its four figures drawn as the members' means over their 5-95 % bands.
TEST_F(Browser, TheDashboardsEnsemblePageRendersItsFiguresWithBands) {
  ASSERT_EQ(shared_->ensemble_submitted.exit_code, 0) << shared_->ensemble_submitted.err;
  const std::string base = "http://127.0.0.1:" + std::to_string(shared_->http_port);
  const std::string dom = chromium(shared_->dir, "--dump-dom", base + "/ensembles/1");
  const json results = render_results(dom);
  ASSERT_TRUE(results.is_object()) << dom.substr(0, 2000);
  EXPECT_TRUE(results["done"].get<bool>());
  EXPECT_TRUE(results["errors"].empty()) << results["errors"].dump();
  ASSERT_EQ(shared_->ensemble_figures.size(), 4u) << shared_->ensemble_figures.dump();
  ASSERT_EQ(results["figures"].size(), 4u) << results.dump();
  // A band and a line per kappa series (1, 2, 5, 10); against kappa, one band, one line, a point each.
  EXPECT_EQ(results["figures"]["conjunctions-over-time"], json({{"area", 4}, {"line", 4}}));
  EXPECT_EQ(results["figures"]["conjunctions-vs-kappa"], json({{"area", 1}, {"line", 1}, {"symbol", 4}}));
  std::set<std::string> types;
  for (const json& f : shared_->ensemble_figures)
    if (f["id"] == "objects-by-type")
      for (const json& row : f["spec"]["layer"][1]["data"]["values"]) types.insert(row["type"]);
  EXPECT_EQ(results["figures"]["objects-by-type"], json({{"area", 1}, {"line", types.size()}}));
  EXPECT_NE(dom.find("3 of 3 members ended"), std::string::npos);
}

TEST_F(Browser, AScreenshotOfTheReportIsNotBlank) {
  const std::string png = shared_->dir.path() + "/report.png";
  chromium(shared_->dir, "--screenshot=" + png, "file://" + shared_->dir.path() + "/report.html");
  const double share = share_not_background(test::read_text(png));
  EXPECT_GT(share, 0.02) << "screenshot " << png;
}

TEST(Report, RefusesAnUnknownRunAndAnUnwritablePath) {
  TempDir dir;
  test::Daemon daemon(dir.path() + "/k.db");
  daemon.start();
  auto unknown = cli(dir, "--server " + daemon.address() + " report 42 -o " + dir.path() + "/r.html");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("run 42 not found"), std::string::npos) << unknown.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path() + "/r.html"));
  auto unwritable = cli(dir, "--server " + daemon.address() + " report 1 -o /nonexistent-dir/r.html");
  EXPECT_EQ(unwritable.exit_code, 2);
  EXPECT_NE(unwritable.err.find("cannot write /nonexistent-dir/r.html"), std::string::npos) << unwritable.err;
}

TEST(Report, ARunningRunGivesAPartialReport) {
  TempDir dir;
  test::Daemon daemon(dir.path() + "/k.db");
  daemon.start();
  // The crossings for 20 days: long enough to be caught running.
  std::string scenario = test::crossings_scenario();
  scenario.replace(scenario.find("duration_days: 0.005"), 20, "duration_days: 20");
  test::write_text(dir.path() + "/long.yaml", scenario);
  ASSERT_EQ(cli(dir, "--server " + daemon.address() + " submit " + dir.path() + "/long.yaml").exit_code, 0);
  std::string shown;
  for (int i = 0; i < 500 && shown.find("running") == std::string::npos; ++i) {
    shown = cli(dir, "--server " + daemon.address() + " show 1").out;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  auto report = cli(dir, "--server " + daemon.address() + " report 1 -o " + dir.path() + "/r.html");
  EXPECT_EQ(report.exit_code, 0) << report.err;
  EXPECT_NE(report.out.find("partial"), std::string::npos) << report.out;
  const std::string html = test::read_text(dir.path() + "/r.html");
  EXPECT_NE(html.find("class=\"partial\""), std::string::npos);
  EXPECT_NE(html.find("not yet: the run has not ended"), std::string::npos);
  cli(dir, "--server " + daemon.address() + " cancel 1");
}

}  // namespace
}  // namespace kessler
