// The shared output formatting, checked against independent readers: strtod for numbers,
// nlohmann::json for string literals and JsonText's documents, an RFC 4180 field reader for CSV.
#include <stio/format.hpp>
#include <stio/json.hpp>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <sstream>

namespace {

using namespace st::io;

double readBack(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

TEST(IoNumber, ShortestFormReadsBackExactly) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> exp(-300, 300);
  for (int i = 0; i < 20000; ++i) {
    const double x = std::ldexp(mant(rng), exp(rng));
    const std::string s = number(x);
    ASSERT_EQ(readBack(s), x) << s;
    // shortest: with one significant digit fewer it no longer reads back (above the 6-digit floor)
    char shorter[40];
    int digits = 0;
    for (int p = 6; p <= 17; ++p) {
      std::snprintf(shorter, sizeof shorter, "%.*g", p, x);
      if (std::string(shorter) == s) {
        digits = p;
        break;
      }
    }
    ASSERT_GT(digits, 0) << s;
    if (digits > 6) {
      std::snprintf(shorter, sizeof shorter, "%.*g", digits - 1, x);
      EXPECT_NE(readBack(shorter), x) << s;
    }
  }
  EXPECT_EQ(number(0.1), "0.1");
  EXPECT_EQ(number(1.0 / 3.0), "0.3333333333333333");  // 16 digits suffice
  EXPECT_EQ(number(1e-5), "1e-05");
  EXPECT_EQ(number(420), "420");
}

TEST(IoNumber, FixedDigitsAndNonFinite) {
  EXPECT_EQ(number(1.0 / 3.0, 9), "0.333333333");
  EXPECT_EQ(number(123456789012345.0, 12), "1.23456789012e+14");
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(number(nan), "nan");
  EXPECT_EQ(number(-nan, 12), "nan");
  EXPECT_EQ(number(inf), "inf");
  EXPECT_EQ(number(-inf, 9), "-inf");
  EXPECT_EQ(jsonNumber(nan), "null");
  EXPECT_EQ(jsonNumber(inf, 17), "null");
  EXPECT_EQ(jsonNumber(0.1, 17), "0.10000000000000001");
  EXPECT_EQ(fixed(2.345, 1), "2.3");
  EXPECT_EQ(fixed(-0.5, 0), "-0");
  EXPECT_EQ(fixed(1e300, 2).size(), 304u);  // 301 digits, the point, two decimals
}

std::string parseJsonString(const std::string& literal) {
  return nlohmann::json::parse("{\"k\": " + literal + "}").at("k").get<std::string>();
}

TEST(IoJson, EveryByteSurvivesAJsonParser) {
  std::string all;
  for (int c = 1; c < 256; ++c) all += static_cast<char>(c);
  const std::string lit = jsonString(all);
  // a JSON string holds no raw control character
  for (std::size_t i = 1; i + 1 < lit.size(); ++i) EXPECT_GE(static_cast<unsigned char>(lit[i]), 0x20u) << i;
  std::string ascii;
  for (int c = 1; c < 128; ++c) ascii += static_cast<char>(c);
  EXPECT_EQ(parseJsonString(jsonString(ascii)), ascii);
  EXPECT_EQ(parseJsonString(jsonString("caf\xc3\xa9 \xe2\x82\xac")), "caf\xc3\xa9 \xe2\x82\xac");
  EXPECT_EQ(jsonString("a\r\nb\t\"\\\x01"), "\"a\\r\\nb\\t\\\"\\\\\\u0001\"");
}

// RFC 4180, one field: quoted fields may hold commas, CR, LF and doubled quotes.
std::string readCsvField(const std::string& f, std::size_t& used) {
  std::string out;
  std::size_t i = 0;
  if (!f.empty() && f[0] == '"') {
    for (i = 1; i < f.size(); ++i) {
      if (f[i] == '"') {
        if (i + 1 < f.size() && f[i + 1] == '"') {
          out += '"';
          ++i;
        } else {
          ++i;
          break;
        }
      } else {
        out += f[i];
      }
    }
  } else {
    while (i < f.size() && f[i] != ',' && f[i] != '\n') out += f[i++];
  }
  used = i;
  return out;
}

TEST(IoCsv, FieldsReadBackAndOnlyNeededOnesAreQuoted) {
  for (const std::string s : {"plain", "", "a,b", "say \"hi\"", "two\nlines", "cr\rhere", "\"", ",", "x y"}) {
    const std::string f = csvField(s);
    std::size_t used = 0;
    EXPECT_EQ(readCsvField(f + ",next", used), s) << f;
    EXPECT_EQ(used, f.size()) << f;
    const bool needs = s.find_first_of(",\"\r\n") != std::string::npos;
    EXPECT_EQ(f != s, needs) << f;
  }
  EXPECT_EQ(oneLine("a\r\nb\nc"), "a  b c");
}

// csvFields, the reader's half: a row of csvField's fields splits back into them, as the
// independent field reader above reads them.
TEST(IoCsv, RowsSplitBackIntoTheirFields) {
  const std::vector<std::string> values = {"plain", "", "a,b", "say \"hi\"", "cr\rhere", "\"", ",", "x y", ",,\"\","};
  for (std::size_t n = 1; n <= values.size(); ++n) {
    std::vector<std::string> row(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(n));
    std::string line;
    for (std::size_t k = 0; k < row.size(); ++k) {
      if (k) line += ',';
      line += csvField(row[k]);
    }
    EXPECT_EQ(csvFields(line), row) << line;
    std::size_t at = 0;
    for (const std::string& v : row) {
      std::size_t used = 0;
      EXPECT_EQ(readCsvField(line.substr(at), used), v) << line;
      at += used + 1;
    }
  }
  EXPECT_EQ(csvFields("a,b\r"), (std::vector<std::string>{"a", "b"}));  // a CRLF file's line
}

}  // namespace

namespace {

using namespace st::io;

// One UTF-8 policy for every output: invalid bytes become U+FFFD, valid UTF-8 stays
TEST(IoUtf8, InvalidBytesBecomeTheReplacementCharacterEverywhere) {
  const std::string fffd = "\xEF\xBF\xBD";
  EXPECT_TRUE(validUtf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x8E\xB1"));
  for (const std::string bad : {"caf\xE9", "\xC0\xAF", "\xED\xA0\x80", "\xF4\x90\x80\x80", "\xE2\x82", "\xFF"})
    EXPECT_FALSE(validUtf8(bad)) << bad;
  EXPECT_EQ(utf8("caf\xE9!"), "caf" + fffd + "!");
  EXPECT_EQ(utf8("\xE2\x82"), fffd + fffd);           // a cut sequence: each byte
  EXPECT_EQ(utf8("caf\xC3\xA9"), "caf\xC3\xA9");      // valid: unchanged
  // JSON: the literal is valid UTF-8 and a JSON parser reads the replacement back
  std::string all;
  for (int c = 1; c < 256; ++c) all += static_cast<char>(c);
  EXPECT_TRUE(validUtf8(jsonString(all)));
  EXPECT_EQ(parseJsonString(jsonString("caf\xE9")), "caf" + fffd);
  // XML: entities, and no character XML 1.0 forbids
  EXPECT_EQ(xmlText("a<b>&\"c\x01\xE9"), "a&lt;b&gt;&amp;&quot;c" + fffd + fffd);
  EXPECT_TRUE(validUtf8(xmlText(all)));
  // CSV
  EXPECT_EQ(csvField("caf\xE9"), "caf" + fffd);
  // a terminal line: no escape sequence reaches the terminal
  EXPECT_EQ(printable("red\x1b[31m\x07\x7f name"), "red\\x1b[31m\\x07\\x7f name");
}

// Ids beginning =, +, -, @ get a leading apostrophe (no spreadsheet formula injection) and read back
TEST(IoCsv, FormulaLikeFieldsAreNeutralisedAndReadBack) {
  EXPECT_EQ(csvField("=HYPERLINK(\"http://x\")"), "\"'=HYPERLINK(\"\"http://x\"\")\"");
  EXPECT_EQ(csvField("+cmd"), "'+cmd");
  EXPECT_EQ(csvField("-1+1"), "'-1+1");
  EXPECT_EQ(csvField("@SUM(A1)"), "'@SUM(A1)");
  EXPECT_EQ(csvField("\tx"), "'\tx");
  // numbers stay numbers
  EXPECT_EQ(csvField("-3.5"), "-3.5");
  EXPECT_EQ(csvField("+1e-3"), "+1e-3");
  EXPECT_EQ(csvField("-"), "'-");
  // every field reads back as it was, an apostrophe of its own included
  for (const std::string s : {"=1+1", "+a", "-b", "@c", "-3.5", "'=x", "''=y", "'plain", "'-5", "-", "=", "\tt", "a=b"}) {
    EXPECT_EQ(csvFields(csvField(s) + "," + csvField(s)), (std::vector<std::string>{s, s})) << s;
    const std::string f = csvField(s);
    EXPECT_TRUE(f.empty() || std::string("=+-@\t").find(f[0]) == std::string::npos ||
                f == csvField("-3.5") || f == "+1e-3" || s == "-3.5")
        << s << " -> " << f;
  }
}

}  // namespace

// a choices list ("a|b|c") into its words, as the settings tables read theirs
TEST(IoSplit, PiecesBetweenTheSeparators) {
  using V = std::vector<std::string_view>;
  EXPECT_EQ(st::io::split("stop|scaling|pfl", '|'), (V{"stop", "scaling", "pfl"}));
  EXPECT_EQ(st::io::split("one", '|'), (V{"one"}));
  EXPECT_EQ(st::io::split("", '|'), V{});
  EXPECT_EQ(st::io::split("a||b", '|'), (V{"a", "", "b"}));
  EXPECT_EQ(st::io::split("a|", '|'), (V{"a"}));
}

// JsonText: literals are structure, other text is a quoted value, doubles jsonNumber's; what it
// writes is what a JSON parser reads back, NaN and infinities as null.
TEST(IoJson, JsonTextWritesWhatAParserReadsBack) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::string name = "a \"quoted\"\n\x01name \xff";
  const char* kind = "rest";  // a const char* from a toString: a value, not structure
  JsonText inner(9);
  inner << "[" << 1.0 / 3.0 << ", " << nan << "]";
  JsonText j(17);
  j << "{\n  \"name\": " << name << ",\n  \"kind\": " << kind << ",\n  \"x\": " << 0.1 << ", \"n\": " << -inf
    << ", \"big\": " << std::uint64_t{18446744073709551615u} << ", \"i\": " << -7 << ", \"ok\": " << jsonBool(true)
    << ", \"none\": " << jsonRaw("null") << ", \"inner\": " << inner << "\n}\n";
  nlohmann::json d;
  ASSERT_NO_THROW(d = nlohmann::json::parse(j.str())) << j.str();
  EXPECT_EQ(d["name"].get<std::string>(), utf8(name));
  EXPECT_EQ(d["kind"].get<std::string>(), "rest");
  EXPECT_EQ(d["x"].get<double>(), 0.1);
  EXPECT_TRUE(d["n"].is_null());
  EXPECT_EQ(d["big"].get<std::uint64_t>(), 18446744073709551615u);
  EXPECT_EQ(d["i"].get<int>(), -7);
  EXPECT_EQ(d["ok"].get<bool>(), true);
  EXPECT_TRUE(d["none"].is_null());
  EXPECT_EQ(d["inner"][0].get<double>(), 0.333333333);  // 9 digits, the inner writer's
  EXPECT_TRUE(d["inner"][1].is_null());
  // the layout is the caller's, byte for byte
  JsonText small;
  small << "{\"a\": " << 1.5 << ", \"b\": " << std::string("x") << "}";
  EXPECT_EQ(small.str(), "{\"a\": 1.5, \"b\": \"x\"}");
}
