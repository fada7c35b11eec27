// Catalog formats and bad input. Reference states come from Debian's python3-sgp4 (Vallado's SGP4,
// official Python port) reading the same files:
//   /usr/bin/python3 -c "from sgp4 import omm; from sgp4.api import Satrec; f=next(omm.parse_csv(
//     open('tests/data/sgp4/sample_omm.csv'))); s=Satrec(); omm.initialize(s,f); print(s.sgp4_tsince(60.0))"
// (and likewise for sample_omm.json and, with its epoch written as 2007-03-05T10:34:41.426400, for
// tests/data/ccsds/OMMExample1.txt).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/catalog/ingest.hpp"
#include "core/catalog/object_properties.hpp"
#include "core/catalog/omm.hpp"
#include "core/catalog/satcat.hpp"
#include "core/catalog/text_fields.hpp"
#include "core/catalog/tle.hpp"

namespace kessler {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string data(const std::string& rel) {
  return read_file(std::string(KESSLER_TEST_DATA_DIR) + "/" + rel);
}

// The first five 3LE sets of the real catalog (CRLF line ends, an unpadded catalog number "   20").
std::vector<std::string> real_lines() {
  const std::string text = read_file(std::string(KESSLER_REPO_DIR) +
                                     "/deploy/datasets/catalog/spacetrack_3le_2022-01-22_ODAP.txt");
  std::vector<std::string> out;
  for (auto line : text::split_lines(text)) {
    if (out.size() == 15) break;
    out.emplace_back(line);
  }
  return out;
}

std::string with_checksum(std::string line) {
  line[68] = static_cast<char>('0' + tle_checksum(line));
  return line;
}

std::string join_crlf(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\r\n";
  return s;
}

IngestRules wide_rules() {
  IngestRules r;
  r.min_perigee_km = -1e9;
  r.max_apogee_km = 1e9;
  r.default_exclusions = false;
  return r;
}

void expect_state(const Sgp4State& s, std::array<double, 3> r_km, std::array<double, 3> v_km_s) {
  ASSERT_EQ(s.error, Sgp4Error::kNone);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(s.position_km[k], r_km[k], 1e-4);
    EXPECT_NEAR(s.velocity_km_s[k], v_km_s[k], 1e-7);
  }
}

TEST(Tle, CatalogNumbersIncludingAlpha5) {
  EXPECT_EQ(decode_catalog_number("00005"), 5u);
  EXPECT_EQ(decode_catalog_number("   20"), 20u);
  EXPECT_EQ(decode_catalog_number("T0000"), 270000u);
  EXPECT_EQ(decode_catalog_number("A0001"), 100001u);
  EXPECT_EQ(decode_catalog_number("J0000"), 180000u);  // I is skipped
  EXPECT_EQ(decode_catalog_number("Z9999"), 339999u);
  EXPECT_FALSE(decode_catalog_number("I0000"));
  EXPECT_FALSE(decode_catalog_number("O0000"));
  EXPECT_FALSE(decode_catalog_number("12a45"));
}

TEST(Tle, RealThreeLineSetsWithCrlfAndUnpaddedNumbers) {
  const auto parsed = parse_tle_text(join_crlf(real_lines()), {}, "real");
  ASSERT_TRUE(parsed.problems.empty()) << parsed.problems.front().message;
  ASSERT_EQ(parsed.sets.size(), 5u);
  EXPECT_EQ(parsed.sets[0].elements.name, "VANGUARD 1");
  EXPECT_EQ(parsed.sets[0].elements.catalog_number, 5u);
  EXPECT_EQ(parsed.sets[4].elements.catalog_number, 20u);
  EXPECT_EQ(parsed.sets[4].line, 13u);
  EXPECT_EQ(parsed.sets[0].elements.epoch.to_iso8601(3), "2022-01-22T13:23:06.236Z");  // day 22.55771106
  EXPECT_NEAR(parsed.sets[0].elements.eccentricity, 0.1843365, 1e-15);
  EXPECT_NEAR(parsed.sets[0].elements.bstar_per_earth_radius, 0.15609e-3, 1e-18);
}

TEST(Tle, AlphaFiveSetOfTheRealCatalog) {
  const std::string text =
      "0 TBA - TO BE ASSIGNED\n"
      "1 T0000U          22022.51724047 -.00000179  00000-0 -66041-3 0  9997\n"
      "2 T0000  90.2852 310.9019 0032565  18.7644 341.4668 12.95239207102052\n";
  const auto parsed = parse_tle_text(text, {}, "alpha5");
  ASSERT_EQ(parsed.sets.size(), 1u);
  EXPECT_EQ(parsed.sets[0].elements.catalog_number, 270000u);
  EXPECT_NEAR(parsed.sets[0].elements.bstar_per_earth_radius, -0.66041e-3, 1e-18);
}

TEST(BadInput, EachBadRecordNamedByLineLenientLoadsTheRest) {
  auto lines = real_lines();
  // Set 2 (lines 4-6): line 2 truncated.           -> file line 6
  lines[5] = lines[5].substr(0, 60);
  // Set 3 (lines 7-9): wrong checksum on line 1.   -> file line 8
  lines[7][68] = lines[7][68] == '0' ? '1' : '0';
  // Set 4 (lines 10-12): letters in the inclination -> file line 12
  lines[11] = with_checksum(lines[11].substr(0, 10) + "A" + lines[11].substr(11));
  // Set 5 (lines 13-15): epoch 22050 = 2022-02-19, 49 days after the start -> file line 13
  lines[13] = with_checksum(lines[13].replace(18, 5, "22050"));
  CatalogInput input;
  input.text = join_crlf(lines);
  input.source = "bad.3le";
  const UtcEpoch start = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0);

  const IngestResult lenient = ingest_catalog(input, wide_rules(), start, 1);
  ASSERT_FALSE(lenient.refused);
  EXPECT_EQ(lenient.report.records, 5u);
  EXPECT_EQ(lenient.report.accepted, 1u);
  EXPECT_EQ(lenient.report.rejected, 4u);
  ASSERT_EQ(lenient.report.rejections.size(), 4u);
  const auto& rj = lenient.report.rejections;
  EXPECT_EQ(rj[0].line, 6u);
  EXPECT_EQ(rj[0].reason_key, "truncated");
  EXPECT_EQ(rj[1].line, 8u);
  EXPECT_EQ(rj[1].reason_key, "checksum");
  EXPECT_EQ(rj[2].line, 12u);
  EXPECT_EQ(rj[2].reason_key, "number");
  EXPECT_NE(rj[2].message.find("inclination"), std::string::npos) << rj[2].message;
  EXPECT_EQ(rj[3].line, 13u);
  EXPECT_EQ(rj[3].reason_key, "epoch");
  EXPECT_EQ(lenient.population.size(), 1u);
  EXPECT_EQ(lenient.population.id[0], 5u);
  const std::string report = lenient.report.text();
  EXPECT_NE(report.find("bad.3le:8: "), std::string::npos) << report;

  IngestRules strict = wide_rules();
  strict.strict = true;
  const IngestResult refused = ingest_catalog(input, strict, start, 1);
  EXPECT_TRUE(refused.refused);
  EXPECT_TRUE(refused.population.empty());
  EXPECT_NE(refused.error.find("line 6"), std::string::npos) << refused.error;
}

TEST(BadInput, OmmEccentricityAboveOneAndMissingFields) {
  const std::string header =
      "OBJECT_NAME,OBJECT_ID,EPOCH,MEAN_MOTION,ECCENTRICITY,INCLINATION,RA_OF_ASC_NODE,ARG_OF_PERICENTER,"
      "MEAN_ANOMALY,EPHEMERIS_TYPE,CLASSIFICATION_TYPE,NORAD_CAT_ID,ELEMENT_SET_NO,REV_AT_EPOCH,BSTAR,"
      "MEAN_MOTION_DOT,MEAN_MOTION_DDOT\n";
  const std::string good =
      "A,2000-001A,2022-01-01T00:00:00,15.5,.001,51.6,10,20,30,0,U,1001,999,1,.1E-3,0,0\n";
  const std::string hyperbolic =
      "B,2000-001B,2022-01-01T00:00:00,15.5,1.2,51.6,10,20,30,0,U,1002,999,1,.1E-3,0,0\n";
  const std::string letters =
      "C,2000-001C,2022-01-01T00:00:00,15.5x,.001,51.6,10,20,30,0,U,1003,999,1,.1E-3,0,0\n";
  const std::string short_row = "D,2000-001D,2022-01-01T00:00:00\n";
  const auto parsed = parse_omm_csv(header + good + hyperbolic + letters + short_row, "omm.csv");
  ASSERT_EQ(parsed.sets.size(), 1u);
  ASSERT_EQ(parsed.problems.size(), 3u);
  EXPECT_EQ(parsed.problems[0].line, 3u);
  EXPECT_EQ(parsed.problems[0].reason_key, "eccentricity");
  EXPECT_NE(parsed.problems[0].message.find("ECCENTRICITY"), std::string::npos);
  EXPECT_EQ(parsed.problems[1].line, 4u);
  EXPECT_NE(parsed.problems[1].message.find("MEAN_MOTION"), std::string::npos);
  EXPECT_EQ(parsed.problems[2].line, 5u);
}

TEST(Omm, CelesTrakCsvAndJsonMatchTheReferenceSgp4) {
  const auto csv = parse_omm_csv(data("sgp4/sample_omm.csv"), "csv");
  ASSERT_EQ(csv.sets.size(), 1u);
  EXPECT_EQ(csv.sets[0].elements.catalog_number, 5u);
  EXPECT_EQ(csv.sets[0].elements.name, "VANGUARD 1");
  expect_state(sgp4_propagate(sgp4_initialise(csv.sets[0].elements), 60.0),
               {5341.823340, 4584.259002, 397.563454}, {-4.009075521, 5.474653212, -4.562170692});
  const auto json = parse_omm_json(data("sgp4/sample_omm.json"), "json");
  ASSERT_EQ(json.sets.size(), 1u);
  expect_state(sgp4_propagate(sgp4_initialise(json.sets[0].elements), 60.0),
               {-6448.912164, -5509.891606, -2106.794525}, {3.369520187, -4.504003444, -3.649998800});
}

TEST(Omm, CcsdsKvnWithDayOfYearEpoch) {
  const auto kvn = parse_omm_kvn(data("ccsds/OMMExample1.txt"), "kvn");
  ASSERT_EQ(kvn.sets.size(), 1u) << (kvn.problems.empty() ? "" : kvn.problems[0].message);
  const MeanElements& el = kvn.sets[0].elements;
  EXPECT_EQ(el.catalog_number, 23581u);
  EXPECT_EQ(el.name, "GOES 9");
  EXPECT_EQ(el.epoch.to_iso8601(4), "2007-03-05T10:34:41.4264Z");
  expect_state(sgp4_propagate(sgp4_initialise(el), 60.0), {-30432.377622, 29155.531518, 1820.893687},
               {-2.122285689, -2.220702779, 0.096457032});
  // SGP4-XP element sets are another theory and are refused.
  const auto xp = parse_omm_kvn(data("ccsds/OMMExample5.txt"), "kvn-xp");
  EXPECT_TRUE(xp.sets.empty());
  ASSERT_EQ(xp.problems.size(), 1u);
  EXPECT_EQ(xp.problems[0].reason_key, "theory");
}

TEST(Omm, XmlFromCelesTrakAndTheCcsdsExample) {
  const auto xml = parse_omm_xml(data("sgp4/sample_omm.xml"), "xml");
  ASSERT_EQ(xml.sets.size(), 1u) << (xml.problems.empty() ? "" : xml.problems[0].message);
  // The same element set as sample_omm.csv, so the same reference state.
  expect_state(sgp4_propagate(sgp4_initialise(xml.sets[0].elements), 60.0),
               {5341.823340, 4584.259002, 397.563454}, {-4.009075521, 5.474653212, -4.562170692});
  const auto ccsds = parse_omm_xml(data("ccsds/OMMExample2.xml"), "ccsds-xml");
  ASSERT_EQ(ccsds.sets.size(), 1u) << (ccsds.problems.empty() ? "" : ccsds.problems[0].message);
  EXPECT_EQ(ccsds.sets[0].elements.catalog_number, 23581u);
  EXPECT_EQ(ccsds.sets[0].line, 2u);
  expect_state(sgp4_propagate(sgp4_initialise(ccsds.sets[0].elements), 60.0),
               {-30432.377622, 29155.531518, 1820.893687}, {-2.122285689, -2.220702779, 0.096457032});
}

TEST(BadInput, EveryPrefixOfEveryFormatParsesWithoutCrashing) {
  // Cut texts anywhere: readers must report, not crash or read out of bounds (run under ASan too).
  const std::string texts[] = {join_crlf(real_lines()), data("sgp4/sample_omm.csv"),
                               data("sgp4/sample_omm.json"), data("ccsds/OMMExample1.txt"),
                               data("sgp4/sample_omm.xml")};
  std::size_t parsed_sets = 0;
  for (const std::string& full : texts) {
    for (std::size_t n = 0; n <= full.size(); ++n) {
      const std::string_view cut(full.data(), n);
      const ElementSetText r = parse_catalog_text(cut, CatalogFormat::kDetect, "cut");
      parsed_sets += r.sets.size();
      for (const auto& p : r.problems) ASSERT_FALSE(p.message.empty());
      (void)parse_satcat_csv(cut, "cut");
      (void)parse_active_list(cut, "cut", nullptr);
    }
  }
  EXPECT_GT(parsed_sets, 0u);
}

TEST(Formats, DetectedFromTheText) {
  EXPECT_EQ(detect_catalog_format(data("sgp4/sample_omm.xml")), CatalogFormat::kOmmXml);
  EXPECT_EQ(detect_catalog_format(data("sgp4/sample_omm.csv")), CatalogFormat::kOmmCsv);
  EXPECT_EQ(detect_catalog_format(data("sgp4/sample_omm.json")), CatalogFormat::kOmmJson);
  EXPECT_EQ(detect_catalog_format(data("ccsds/OMMExample1.txt")), CatalogFormat::kOmmKvn);
  EXPECT_EQ(detect_catalog_format(join_crlf(real_lines())), CatalogFormat::kTle);
}

TEST(Satcat, CelesTrakStatusAndNumericRcs) {
  const std::string satcat =
      "OBJECT_NAME,OBJECT_ID,NORAD_CAT_ID,OBJECT_TYPE,OPS_STATUS_CODE,OWNER,LAUNCH_DATE,LAUNCH_SITE,DECAY_"
      "DATE,"
      "PERIOD,INCLINATION,APOGEE,PERIGEE,RCS,DATA_STATUS_CODE,ORBIT_CENTER,ORBIT_TYPE\n"
      "A,2000-001A,1001,PAY,+,US,2000-01-01,AFETR,,95,51.6,500,480,3.1416,,EA,ORB\n"
      "B,2000-001B,1002,DEB,,US,2000-01-01,AFETR,,95,51.6,500,480,0.00001,,EA,ORB\n"
      "C,2000-001C,1003,R/B,-,US,2000-01-01,AFETR,,95,51.6,500,480,,,EA,ORB\n";
  const auto table = parse_satcat_csv(satcat, "celestrak");
  EXPECT_EQ(table.flavour, "celestrak");
  ASSERT_EQ(table.entries.size(), 3u);
  EXPECT_EQ(table.entries.at(1001).object_type, "PAYLOAD");
  EXPECT_EQ(table.entries.at(1003).object_type, "ROCKET BODY");
  EXPECT_EQ(table.entries.at(1001).size_class, RcsSizeClass::kLarge);

  const std::string header =
      "OBJECT_NAME,OBJECT_ID,EPOCH,MEAN_MOTION,ECCENTRICITY,INCLINATION,RA_OF_ASC_NODE,ARG_OF_PERICENTER,"
      "MEAN_ANOMALY,EPHEMERIS_TYPE,CLASSIFICATION_TYPE,NORAD_CAT_ID,ELEMENT_SET_NO,REV_AT_EPOCH,BSTAR,"
      "MEAN_MOTION_DOT,MEAN_MOTION_DDOT\n";
  CatalogInput input;
  input.text = header + "A,2000-001A,2022-01-01T00:00:00,15.5,.001,51.6,10,20,30,0,U,1001,999,1,0,0,0\n" +
               "B,2000-001B,2022-01-01T00:00:00,15.5,.001,51.6,10,20,35,0,U,1002,999,1,.1E-3,0,0\n" +
               "C,2000-001C,2022-01-01T00:00:00,15.5,.001,51.6,10,20,40,0,U,1003,999,1,.1E-3,0,0\n";
  input.satcat_csv = satcat;
  IngestRules rules;
  const auto result = ingest_catalog(input, rules, UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0), 1);
  ASSERT_EQ(result.population.size(), 2u);
  EXPECT_EQ(result.report.filtered("radius below minimum"), 1u);  // RCS 1e-5 m^2: r = 1.8 mm
  const auto a = *result.population.index_of(1001);
  EXPECT_NEAR(result.population.radius_m[a], 1.0, 1e-5);  // sqrt(3.1416 / pi)
  EXPECT_EQ(result.population.status[a], ObjectStatus::kActive);
  // BSTAR 0: drag from Cd = 2.2 and the size.
  EXPECT_NEAR(result.population.drag_area_to_mass_m2_kg[a],
              2.2 * 3.14159265358979 * 1.0 / result.population.mass_kg[a], 1e-6);
  EXPECT_EQ(result.population.status[*result.population.index_of(1003)], ObjectStatus::kPassive);

  IngestRules types = rules;
  types.object_types = {"PAYLOAD"};
  const auto only_payloads = ingest_catalog(input, types, UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0), 1);
  EXPECT_EQ(only_payloads.population.size(), 1u);
  EXPECT_EQ(only_payloads.report.filtered("object type"), 2u);
}

TEST(Rules, DockedVehiclesSharingAStationsElementSetAreDroppedOnce) {
  // As in the real catalog: a visiting vehicle is published with a copy of its station's element set.
  const std::string header =
      "OBJECT_NAME,OBJECT_ID,EPOCH,MEAN_MOTION,ECCENTRICITY,INCLINATION,RA_OF_ASC_NODE,ARG_OF_PERICENTER,"
      "MEAN_ANOMALY,EPHEMERIS_TYPE,CLASSIFICATION_TYPE,NORAD_CAT_ID,ELEMENT_SET_NO,REV_AT_EPOCH,BSTAR,"
      "MEAN_MOTION_DOT,MEAN_MOTION_DDOT\n";
  CatalogInput input;
  input.text = header +
               "STATION,2021-001A,2022-01-01T00:00:00,15.5,.0005,41.5,10,20,30,0,U,2001,999,1,.2E-3,0,0\n" +
               "CARGO,2021-002A,2022-01-01T00:00:00,15.5,.0005,41.5,10,20,30,0,U,2002,999,1,.2E-3,0,0\n" +
               "CREW,2021-003A,2022-01-01T00:00:00,15.5,.0005,41.5,10,20,30,0,U,2003,999,1,.2E-3,0,0\n" +
               "FREE,2021-004A,2022-01-01T00:00:00,15.5,.0005,41.5,10,20,31,0,U,2004,999,1,.2E-3,0,0\n";
  const UtcEpoch start = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0);
  const auto result = ingest_catalog(input, IngestRules{}, start, 1);
  EXPECT_EQ(result.report.filtered("docked"), 2u);
  ASSERT_EQ(result.population.size(), 2u);
  EXPECT_EQ(result.population.id, (std::vector<ObjectId>{2001, 2004}));

  IngestRules keep;
  keep.drop_docked = false;
  EXPECT_EQ(ingest_catalog(input, keep, start, 1).population.size(), 4u);
}

TEST(Rules, MassLawAndGlobs) {
  // (4/3) pi r^3 2698.9 at r = 5 mm; (4/3) pi 92.937 2^-0.74 at r = 1 m.
  EXPECT_NEAR(mass_from_radius_kg(0.005), 1.4131e-3, 1e-7);
  EXPECT_NEAR(mass_from_radius_kg(1.0), 233.085, 0.001);  // python3: 4/3*pi*92.937*2**-0.74
  EXPECT_NEAR(drag_area_to_mass_from_bstar(1e-4), 2e-4 / 0.15696615, 1e-18);
  EXPECT_TRUE(glob_match("STARLINK*", "Starlink-1007"));
  EXPECT_TRUE(glob_match("ISS (ZARYA)", "ISS (ZARYA)"));
  EXPECT_FALSE(glob_match("ISS (ZARYA)", "ISS DEB"));
  // The paper leaves out the ISS: every module catalogued as "ISS (...)", never the free debris.
  EXPECT_TRUE(glob_match("ISS (*)", "ISS (NAUKA)"));
  EXPECT_FALSE(glob_match("ISS (*)", "ISS DEB"));
  EXPECT_TRUE(glob_match("*DEB*", "COSMOS 2251 DEB"));
  EXPECT_FALSE(glob_match("ONEWEB*", "XONEWEB"));
}

TEST(Rules, SampledRadiiFollowTheClassDistribution) {
  SizeSampling s;
  double sum = 0, sum2 = 0;
  const int n = 20000;
  for (int id = 0; id < n; ++id) {
    const double r = sample_radius_m(s, RcsSizeClass::kMedium, 3, static_cast<std::uint64_t>(id));
    sum += r;
    sum2 += r * r;
    ASSERT_GE(r, s.min_radius_m);
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.37, 0.003);  // 4 standard errors of the mean
  EXPECT_NEAR(sd, 0.10, 0.003);
}

}  // namespace
}  // namespace kessler
