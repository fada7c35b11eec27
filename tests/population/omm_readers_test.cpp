// The OMM JSON (simdjson) and XML (pugixml) readers: the same element sets as the KVN reader, errors that
// name the record, field and line, and hostile XML refused with its reason instead of a hang or crash.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>

#include "core/catalog/ingest.hpp"
#include "core/catalog/omm.hpp"

namespace kessler {
namespace {

std::string data(const std::string& rel) {
  std::ifstream in(std::string(KESSLER_TEST_DATA_DIR) + "/" + rel, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Names aside: the two CCSDS example files spell them differently ("GOES 9", "GOES-9").
void expect_same_elements(const MeanElements& a, const MeanElements& b) {
  EXPECT_EQ(a.catalog_number, b.catalog_number);
  EXPECT_EQ(a.international_designator, b.international_designator);
  EXPECT_EQ(a.epoch.to_iso8601(6), b.epoch.to_iso8601(6));
  EXPECT_EQ(a.mean_motion_rad_min, b.mean_motion_rad_min);
  EXPECT_EQ(a.eccentricity, b.eccentricity);
  EXPECT_EQ(a.inclination_rad, b.inclination_rad);
  EXPECT_EQ(a.raan_rad, b.raan_rad);
  EXPECT_EQ(a.argument_of_perigee_rad, b.argument_of_perigee_rad);
  EXPECT_EQ(a.mean_anomaly_rad, b.mean_anomaly_rad);
  EXPECT_EQ(a.bstar_per_earth_radius, b.bstar_per_earth_radius);
}

const char* kJsonRecord =
    "{\"OBJECT_NAME\": \"VANGUARD 1\", \"OBJECT_ID\": \"1958-002B\", \"EPOCH\": "
    "\"2025-02-14T14:36:48.662784\",\n"
    " \"MEAN_MOTION\": 10.85873516, \"ECCENTRICITY\": 0.1841322, \"INCLINATION\": 34.2493,\n"
    " \"RA_OF_ASC_NODE\": 19.2327, \"ARG_OF_PERICENTER\": 100.1057, \"MEAN_ANOMALY\": 281.1229,\n"
    " \"EPHEMERIS_TYPE\": 0, \"NORAD_CAT_ID\": 5, \"BSTAR\": 0.00035436, \"MEAN_MOTION_DOT\": 2.64e-6}";

TEST(OmmJson, ArrayOfRecordsWithTheirLinesAndNestedValuesSkipped) {
  const std::string text =
      std::string("[\n") + kJsonRecord + ",\n" + kJsonRecord +
      ",\n{\"norad_cat_id\": \"7\", \"EXTRA\": {\"a\": [1, {\"b\": null}]}, \"EPOCH\": null}\n]";
  const ElementSetText r = parse_omm_json(text, "j");
  ASSERT_EQ(r.sets.size(), 2u);
  EXPECT_EQ(r.sets[0].line, 2u);
  EXPECT_EQ(r.sets[1].line, 6u);
  EXPECT_EQ(r.sets[0].elements.name, "VANGUARD 1");
  EXPECT_EQ(r.sets[0].elements.bstar_per_earth_radius, 0.00035436);
  // Keys are matched case-insensitively; a null is a missing field.
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_EQ(r.problems[0].line, 10u);
  EXPECT_EQ(r.problems[0].reason_key, "missing");
  EXPECT_NE(r.problems[0].message.find("NORAD_CAT_ID 7"), std::string::npos) << r.problems[0].message;
  EXPECT_NE(r.problems[0].message.find("EPOCH"), std::string::npos) << r.problems[0].message;
  // A single object is a catalog of one.
  EXPECT_EQ(parse_omm_json(kJsonRecord, "j").sets.size(), 1u);
  EXPECT_TRUE(parse_omm_json("[]", "j").sets.empty());
}

TEST(OmmJson, MalformedJsonNamesTheRecordFieldAndLine) {
  const std::string text = std::string("[\n") + kJsonRecord + ",\n{\"NORAD_CAT_ID\": 7,\n \"BSTAR\": tru}\n]";
  const ElementSetText r = parse_omm_json(text, "bad.json");
  EXPECT_TRUE(r.sets.empty());  // one bad spot: nothing taken from the text
  ASSERT_EQ(r.problems.size(), 1u);
  const ParseProblem& p = r.problems[0];
  EXPECT_EQ(p.reason_key, "json");
  EXPECT_EQ(p.source, "bad.json");
  EXPECT_NE(p.message.find("record 2"), std::string::npos) << p.message;
  EXPECT_NE(p.message.find("field BSTAR"), std::string::npos) << p.message;
  EXPECT_EQ(p.line, 7u) << p.message;

  for (const char* bad :
       {"[{\"A\": 1} {\"B\": 2}]", "[{\"A\": 1}] x", "{\"A\" 1}", "[{\"A\": \"unterminated}]", "7", ""}) {
    const ElementSetText b = parse_omm_json(bad, "bad");
    EXPECT_TRUE(b.sets.empty()) << bad;
    ASSERT_EQ(b.problems.size(), 1u) << bad;
    EXPECT_EQ(b.problems[0].reason_key, "json") << bad;
    EXPECT_NE(b.problems[0].message.find("not OMM JSON"), std::string::npos) << b.problems[0].message;
  }
}

TEST(OmmXml, SameElementsAsTheKvnOfTheCcsdsExamples) {
  for (const char* name : {"ccsds/OMMExample2", "ccsds/OMMExample4"}) {
    const ElementSetText xml = parse_omm_xml(data(std::string(name) + ".xml"), "xml");
    const ElementSetText kvn = parse_omm_kvn(data(std::string(name) + ".txt"), "kvn");
    ASSERT_EQ(xml.sets.size(), 1u) << name << (xml.problems.empty() ? "" : xml.problems[0].message);
    ASSERT_EQ(kvn.sets.size(), 1u) << name;
    expect_same_elements(xml.sets[0].elements, kvn.sets[0].elements);
  }
  // Detected and read through the catalog entry point as well.
  const ElementSetText detected =
      parse_catalog_text(data("sgp4/sample_omm.xml"), CatalogFormat::kDetect, "xml");
  ASSERT_EQ(detected.sets.size(), 1u);
  EXPECT_EQ(detected.sets[0].elements.catalog_number, 5u);
  EXPECT_EQ(detected.sets[0].line, 3u);
}

TEST(OmmXml, BillionLaughsIsRefusedForItsDoctype) {
  std::string text = "<?xml version=\"1.0\"?>\n<!DOCTYPE lolz [\n <!ENTITY lol \"lol\">\n";
  for (int i = 1; i <= 9; ++i) {
    text += " <!ENTITY lol" + std::to_string(i) + " \"";
    for (int k = 0; k < 10; ++k) text += i == 1 ? "&lol;" : "&lol" + std::to_string(i - 1) + ";";
    text += "\">\n";
  }
  text += "]>\n<ndm><omm><OBJECT_NAME>&lol9;</OBJECT_NAME></omm></ndm>\n";
  const auto t0 = std::chrono::steady_clock::now();
  const ElementSetText r = parse_omm_xml(text, "lolz.xml");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
  EXPECT_TRUE(r.sets.empty());
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_EQ(r.problems[0].reason_key, "xml");
  EXPECT_EQ(r.problems[0].line, 2u);
  EXPECT_NE(r.problems[0].message.find("DOCTYPE"), std::string::npos) << r.problems[0].message;
  // An undeclared entity is left as it is, never expanded.
  const ElementSetText plain = parse_omm_xml("<omm><OBJECT_NAME>&lol9;</OBJECT_NAME></omm>", "x");
  ASSERT_EQ(plain.problems.size(), 1u);
  EXPECT_EQ(plain.problems[0].reason_key, "missing");
}

TEST(OmmXml, DeepNestingIsRefusedWithoutExhaustingTheStack) {
  for (const std::size_t depth : {65u, 1000000u}) {
    std::string text = "<?xml version=\"1.0\"?>\n";
    for (std::size_t i = 0; i < depth; ++i) text += "<a>";
    for (std::size_t i = 0; i < depth; ++i) text += "</a>";
    const ElementSetText r = parse_omm_xml(text, "deep.xml");
    EXPECT_TRUE(r.sets.empty());
    ASSERT_EQ(r.problems.size(), 1u);
    EXPECT_EQ(r.problems[0].reason_key, "xml");
    EXPECT_EQ(r.problems[0].line, 2u);
    EXPECT_NE(r.problems[0].message.find("nested deeper than 64"), std::string::npos)
        << r.problems[0].message;
  }
  // 64 levels are allowed (OMM needs six).
  std::string ok;
  for (int i = 0; i < 62; ++i) ok += "<a>";
  ok += "<omm><NORAD_CAT_ID>5</NORAD_CAT_ID></omm>";
  for (int i = 0; i < 62; ++i) ok += "</a>";
  const ElementSetText r = parse_omm_xml(ok, "ok.xml");
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_EQ(r.problems[0].message.find("nested"), std::string::npos) << r.problems[0].message;
}

TEST(OmmXml, MalformedXmlNamesTheLineAndReason) {
  const std::string text =
      "<ndm>\n<omm>\n<EPOCH>2020-01-01T00:00:00</EPOCH>\n<NORAD_CAT_ID>5</NORAD_CAT>\n</omm>\n</ndm>\n";
  const ElementSetText r = parse_omm_xml(text, "bad.xml");
  EXPECT_TRUE(r.sets.empty());
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_EQ(r.problems[0].reason_key, "xml");
  EXPECT_EQ(r.problems[0].source, "bad.xml");
  EXPECT_EQ(r.problems[0].line, 4u) << r.problems[0].message;
  EXPECT_NE(r.problems[0].message.find("not OMM XML: line 4: "), std::string::npos) << r.problems[0].message;
  for (const char* bad : {"<omm>", "<omm><A>1</B></omm>", "<", "<omm a=></omm>", "</omm>"}) {
    const ElementSetText b = parse_omm_xml(bad, "bad");
    EXPECT_TRUE(b.sets.empty()) << bad;
    ASSERT_EQ(b.problems.size(), 1u) << bad;
    EXPECT_EQ(b.problems[0].reason_key, "xml") << bad;
  }
}

}  // namespace
}  // namespace kessler
