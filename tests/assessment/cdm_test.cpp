// CDM reading and writing: every example of tests/data/ccsds loads (KVN and XML), the Alfano test cases'
// Pc from their own states and covariances, bad input named by line and keyword, and round trips.
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/assessment/cdm.hpp"
#include "core/assessment/cdm_conjunction.hpp"
#include "core/assessment/cdm_export.hpp"

namespace kessler::assessment {
namespace {

std::string read_data(const std::string& name) {
  std::ifstream in(std::string(KESSLER_TEST_DATA_DIR) + "/ccsds/" + name, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string joined(const std::vector<CdmError>& errors) {
  std::string out;
  for (const auto& e : errors) out += e.message + "\n";
  return out;
}

CdmConjunction load(const std::string& text, std::vector<CdmError>& errors) {
  Cdm cdm;
  CdmConjunction c;
  if (read_cdm(text, cdm, errors)) read_conjunction(cdm, c, errors);
  return c;
}

TEST(CdmReader, LoadsEveryExampleWithoutAnError) {
  for (const char* name :
       {"CDMExample1.txt", "CDMExample1.xml", "CDMExample2.txt", "CDMExample3.txt", "CDMExample4.txt",
        "ION_SCV8_vs_STARLINK_1233.txt", "AlfanoTestCase01.cdm", "AlfanoTestCase11.cdm"}) {
    std::vector<CdmError> errors;
    const CdmConjunction c = load(read_data(name), errors);
    EXPECT_TRUE(errors.empty()) << name << ":\n" << joined(errors);
    EXPECT_TRUE(c.objects[0].state.rtn_covariance_m2.has_value()) << name;
    EXPECT_TRUE(c.objects[1].state.rtn_covariance_m2.has_value()) << name;
    EXPECT_GT(c.objects[0].state.r_m.norm(), 6.0e6) << name;
  }
}

TEST(CdmReader, KvnAndXmlOfTheAnnexExampleAgree) {
  std::vector<CdmError> errors;
  const CdmConjunction kvn = load(read_data("CDMExample1.txt"), errors);
  const CdmConjunction xml = load(read_data("CDMExample1.xml"), errors);
  ASSERT_TRUE(errors.empty()) << joined(errors);
  EXPECT_EQ(kvn.tca, xml.tca);
  EXPECT_EQ(kvn.miss_distance_m, 715.0);
  EXPECT_EQ(xml.miss_distance_m, 715.0);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(kvn.objects[i].state.r_m, xml.objects[i].state.r_m);
    EXPECT_EQ(*kvn.objects[i].state.rtn_covariance_m2, *xml.objects[i].state.rtn_covariance_m2);
  }
  EXPECT_EQ(xml.cdm_pc, 4.835e-05);
}

TEST(CdmReader, ReadsAUnicodeMinusAndCrlfLineEnds) {
  Cdm cdm;
  std::vector<CdmError> errors;
  ASSERT_TRUE(read_cdm(read_data("CDMExample1.txt"), cdm, errors));
  EXPECT_EQ(Cdm::find(cdm.objects[0], "INTERNATIONAL_DESIGNATOR")->value, "1997-030E");
  std::string crlf;
  for (const char ch : read_data("AlfanoTestCase02.cdm")) {
    if (ch == '\n') crlf += '\r';
    crlf += ch;
  }
  const CdmConjunction a = load(read_data("AlfanoTestCase02.cdm"), errors);
  const CdmConjunction b = load(crlf, errors);
  ASSERT_TRUE(errors.empty()) << joined(errors);
  EXPECT_EQ(a.objects[1].state.v_m_s, b.objects[1].state.v_m_s);
  EXPECT_EQ(*a.objects[1].state.rtn_covariance_m2, *b.objects[1].state.rtn_covariance_m2);
  // A Unicode minus in a number reads as a minus.
  std::string text = read_data("AlfanoTestCase02.cdm");
  const auto at = text.find("= -", text.find("RELATIVE_POSITION_R"));
  ASSERT_NE(at, std::string::npos);
  text.replace(at + 2, 1, "\xE2\x88\x92");
  Cdm minus;
  ASSERT_TRUE(read_cdm(text, minus, errors));
  EXPECT_TRUE(Cdm::find(minus.relative, "RELATIVE_POSITION_R")->value.starts_with("-"));
}

struct AlfanoCase {
  const char* file;
  double expected_pc;
  bool short_encounter;  // Alfano's cases 3 and 5 only: the others are slow (GEO, co-orbiting) encounters
};

TEST(CdmPc, AlfanoTestCasesFromTheirOwnStatesAndCovariances) {
  // NASA CARA's expected values (pc_expected_values.json), HBR from each CDM's own comment.
  // The expected values are 2-D Pc too, so they agree everywhere; the flag tells which are not 2-D
  // problems (encounters lasting from 15 minutes to 3 days against their orbits' periods).
  const AlfanoCase cases[] = {
      {"AlfanoTestCase01.cdm", 0.146749549, false}, {"AlfanoTestCase02.cdm", 0.006222267, false},
      {"AlfanoTestCase03.cdm", 0.100351176, true},  {"AlfanoTestCase04.cdm", 0.049323406, false},
      {"AlfanoTestCase05.cdm", 0.044487386, true},  {"AlfanoTestCase06.cdm", 0.004335455, false},
      {"AlfanoTestCase07.cdm", 0.000158147, false}, {"AlfanoTestCase08.cdm", 0.036948008, false},
      {"AlfanoTestCase09.cdm", 0.290146291, false}, {"AlfanoTestCase11.cdm", 0.002672026, false}};
  for (const auto& c : cases) {
    std::vector<CdmError> errors;
    const CdmConjunction conjunction = load(read_data(c.file), errors);
    ASSERT_TRUE(errors.empty()) << c.file << ": " << joined(errors);
    const double hbr = choose_hard_body_radius(conjunction, std::nullopt);
    const Assessment foster = assess_cdm(conjunction, hbr, PcMethod::kFoster);
    ASSERT_TRUE(foster.pc_computed) << c.file;
    EXPECT_NEAR(foster.pc / c.expected_pc, 1.0, 0.01) << c.file;
    EXPECT_EQ(foster.short_encounter, c.short_encounter)
        << c.file << ": " << foster.encounter_duration_s << " s";
    const Assessment chan = assess_cdm(conjunction, hbr, PcMethod::kChan);
    EXPECT_NEAR(chan.pc / c.expected_pc, 1.0, 0.01) << c.file << " (" << method_name(chan.method) << ")";
  }
}

TEST(CdmPc, TheStarlinkCdmsOwnPcIsReproduced) {
  // A real CSpOC CDM (ITRF states, each object's 5 m exclusion radius in a comment): its own Pc
  // 0.004450713 (FOSTER-1992). Ours from the printed states and covariances is 21 % lower: the
  // message's RTN frames for Earth-fixed states are not stated (we take them inertial) and the printed
  // relative position differs from the states' by 3 m; the test pins the magnitude.
  std::vector<CdmError> errors;
  const CdmConjunction c = load(read_data("ION_SCV8_vs_STARLINK_1233.txt"), errors);
  ASSERT_TRUE(errors.empty()) << joined(errors);
  ASSERT_EQ(c.hard_body_radius_m, 10.0);
  const Assessment a = assess_cdm(c, 10.0, PcMethod::kFoster);
  ASSERT_TRUE(a.pc_computed);
  EXPECT_NEAR(a.pc / *c.cdm_pc, 1.0, 0.25);
  EXPECT_TRUE(a.short_encounter);
}

bool has_error(const std::vector<CdmError>& errors, std::size_t line, std::string_view keyword) {
  for (const auto& e : errors)
    if (e.line == line && e.keyword == keyword) return true;
  return false;
}

std::string replace_line(std::string text, std::string_view keyword, std::string_view replacement) {
  const auto at = text.find(std::string("\n") + std::string(keyword) + " ");
  const auto end = text.find('\n', at + 1);
  return text.replace(at + 1, end - at - 1, replacement);
}

TEST(CdmBadInput, AMissingMandatoryKeywordIsNamedWithItsSection) {
  const std::string text = replace_line(read_data("AlfanoTestCase06.cdm"), "CT_T", "");
  std::vector<CdmError> errors;
  load(text, errors);
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors[0].keyword, "CT_T");
  EXPECT_NE(errors[0].message.find("mandatory keyword missing from OBJECT1"), std::string::npos)
      << errors[0].message;
}

TEST(CdmBadInput, BadNumbersAndUnitsAreNamedByLineAndKeyword) {
  std::string text =
      replace_line(read_data("AlfanoTestCase06.cdm"), "MISS_DISTANCE", "MISS_DISTANCE = 12O.5 [m]");
  text = replace_line(text, "X_DOT", "X_DOT = 3.0 [m/s]");
  std::vector<CdmError> errors;
  load(text, errors);
  EXPECT_TRUE(has_error(errors, 6, "MISS_DISTANCE")) << joined(errors);
  bool unit_named = false;
  for (const auto& e : errors)
    unit_named |= e.keyword == "X_DOT" && e.message.find("[m/s] where [km/s]") != std::string::npos;
  EXPECT_TRUE(unit_named) << joined(errors);
  errors.clear();
  Cdm cdm;
  EXPECT_FALSE(read_cdm("CCSDS_CDM_VERS = 1.0\nthis is not a keyword line\n", cdm, errors));
  EXPECT_TRUE(has_error(errors, 2, "")) << joined(errors);
}

TEST(CdmBadInput, ANonPositiveDefiniteCovarianceIsReportedAndGivesNoPc) {
  // CT_R larger than sqrt(CR_R * CT_T): a correlation above 1.
  const std::string text = replace_line(read_data("AlfanoTestCase06.cdm"), "CT_R", "CT_R = 1.0e+06 [m**2]");
  std::vector<CdmError> errors;
  const CdmConjunction c = load(text, errors);
  ASSERT_EQ(errors.size(), 1u) << joined(errors);
  EXPECT_EQ(errors[0].keyword, "CR_R");
  EXPECT_NE(errors[0].message.find("not positive definite"), std::string::npos);
  EXPECT_FALSE(c.objects[0].state.rtn_covariance_m2.has_value());
  const Assessment a = assess_cdm(c, 10.0);
  EXPECT_FALSE(a.pc_computed);
  EXPECT_TRUE(std::isnan(a.pc));
}

TEST(CdmBadInput, AnXmlBombAndAHundredMegabyteFileAreRefusedQuickly) {
  const std::string bomb =
      "<?xml version=\"1.0\"?>\n<!DOCTYPE cdm [\n<!ENTITY a \"aaaaaaaaaa\">\n"
      "<!ENTITY b \"&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;\">\n<!ENTITY c \"&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;\">\n]>\n"
      "<cdm version=\"1.0\"><header><ORIGINATOR>&c;</ORIGINATOR></header></cdm>\n";
  Cdm cdm;
  std::vector<CdmError> errors;
  EXPECT_FALSE(read_cdm(bomb, cdm, errors));
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors[0].line, 2u);
  EXPECT_NE(errors[0].message.find("DOCTYPE"), std::string::npos);
  std::string huge = read_data("AlfanoTestCase06.cdm");
  huge.resize(100u << 20, ' ');
  const auto start = std::chrono::steady_clock::now();
  errors.clear();
  EXPECT_FALSE(read_cdm(huge, cdm, errors));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));  // no hang (not a speed test)
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].message.find("over the limit"), std::string::npos);
  errors.clear();
  EXPECT_FALSE(read_cdm("<cdm><header>", cdm, errors));  // truncated XML
  EXPECT_FALSE(errors.empty());
}

Encounter sample_encounter() {
  Encounter e;
  e.id1 = 25544;
  e.id2 = 48274;
  e.tca_s = 3723.25;
  e.r1_m = {6771000.0, 12.5, -3.0};
  e.v1_m_s = {0.0, 4800.0, 6000.0};
  e.r2_m = e.r1_m + Eigen::Vector3d(150.0, -320.0, 410.0);
  e.v2_m_s = {-10.0, -5000.0, 5900.0};
  e.miss_distance_m = (e.r2_m - e.r1_m).norm();
  e.relative_speed_m_s = (e.v2_m_s - e.v1_m_s).norm();
  e.kappa = e.miss_distance_m / 12.0;
  return e;
}

void expect_same_fields(const Cdm& a, const Cdm& b) {
  auto same = [](const std::vector<CdmField>& x, const std::vector<CdmField>& y, const char* where) {
    ASSERT_EQ(x.size(), y.size()) << where;
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_EQ(x[i].keyword, y[i].keyword) << where << " " << i;
      EXPECT_EQ(x[i].value, y[i].value) << where << " " << x[i].keyword;
      EXPECT_EQ(x[i].unit, y[i].unit) << where << " " << x[i].keyword;
    }
  };
  same(a.header, b.header, "header");
  same(a.relative, b.relative, "relative");
  same(a.objects[0], b.objects[0], "object 1");
  same(a.objects[1], b.objects[1], "object 2");
}

TEST(CdmRoundTrip, WrittenCdmsReadBackToTheSameValuesAndPassTheMandatoryCheck) {
  CdmExportOptions options;
  options.message_id = "RUN1_SEQ7";
  options.creation_date = UtcEpoch::from_calendar(2026, 3, 10, 12, 0, 0.0);
  options.scenario_epoch = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0.0);
  const Cdm written =
      cdm_from_encounter(sample_encounter(), {25544, "ISS (ZARYA)", {ObjectType::kPayload, 0.5}},
                         {48274, "CZ-5B R/B", {ObjectType::kRocketBody, 1.0}}, options);
  for (const bool xml : {false, true}) {
    const std::string text = xml ? write_cdm_xml(written) : write_cdm_kvn(written);
    Cdm read;
    std::vector<CdmError> errors;
    ASSERT_TRUE(xml ? read_cdm_xml(text, read, errors) : read_cdm_kvn(text, read, errors)) << joined(errors);
    expect_same_fields(written, read);
    CdmConjunction c;
    EXPECT_TRUE(read_conjunction(read, c, errors)) << joined(errors);
    EXPECT_EQ(c.tca, "2022-01-01T01:02:03.250000");
    EXPECT_NEAR(c.miss_distance_m, sample_encounter().miss_distance_m, 5e-4);
    EXPECT_NEAR((c.objects[1].state.r_m - sample_encounter().r2_m).norm(), 0.0, 1e-6);
    // The Pc recomputed from the written message equals the one written (to its 7 printed digits).
    const Assessment again = assess_cdm(c, *c.hard_body_radius_m, PcMethod::kChan);
    EXPECT_NEAR(again.pc / *c.cdm_pc, 1.0, 1e-5);
  }
}

TEST(CdmRoundTrip, TheExamplesSurviveKvnAndXmlRewriting) {
  for (const char* name :
       {"CDMExample1.txt", "CDMExample1.xml", "CDMExample2.txt", "ION_SCV8_vs_STARLINK_1233.txt"}) {
    Cdm original;
    std::vector<CdmError> errors;
    ASSERT_TRUE(read_cdm(read_data(name), original, errors)) << joined(errors);
    Cdm from_kvn;
    Cdm from_xml;
    ASSERT_TRUE(read_cdm_kvn(write_cdm_kvn(original), from_kvn, errors)) << joined(errors);
    ASSERT_TRUE(read_cdm_xml(write_cdm_xml(original), from_xml, errors)) << joined(errors);
    expect_same_fields(original, from_kvn);
    expect_same_fields(original, from_xml);
  }
}

}  // namespace
}  // namespace kessler::assessment
