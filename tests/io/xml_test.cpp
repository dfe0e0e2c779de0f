// The one XML reader: tags and attributes, entities, skipped markup, balance, and errors that name
// the file and line in the reader's own exception type.
#include <stio/xml.hpp>

#include <gtest/gtest.h>

#include "errors.hpp"

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace st::io;

struct TestError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string errorOf(const std::function<void()>& f) { return st::test::errorOf<TestError>(f); }

// every tag of text, as "name" / "/name" / "name/"
std::vector<std::string> tagsOf(const std::string& text, bool balanced = false) {
  XmlScanner x(text, "t.xml", raiseAs<TestError>);
  if (balanced) x.requireBalanced();
  std::vector<std::string> out;
  XmlScanner::Tag t;
  while (x.next(t)) out.push_back((t.closing ? "/" : "") + t.name + (t.selfClosing ? "/" : ""));
  return out;
}

TEST(Xml, ReadsTagsAndAttributesSkippingDeclarationsAndComments) {
  XmlScanner x(std::string("<?xml version=\"1.0\"?>\n<!-- <no> -->\n<!DOCTYPE net>\n<net a=\"1\" b='x &amp; &lt;y&gt;'>\n"
                           "  <lane id=\"l&quot;0\" w = \"3.2\"/>\n</net>\n"),
               "t.xml", raiseAs<TestError>);
  XmlScanner::Tag t;
  ASSERT_TRUE(x.next(t));
  EXPECT_EQ(t.name, "net");
  EXPECT_EQ(t.line, 4);
  ASSERT_NE(t.attr("b"), nullptr);
  EXPECT_EQ(*t.attr("b"), "x & <y>");
  ASSERT_TRUE(x.next(t));
  EXPECT_EQ(t.name, "lane");
  EXPECT_TRUE(t.selfClosing);
  EXPECT_EQ(*t.attr("id"), "l\"0");
  EXPECT_EQ(required(x, t, "w"), 3.2);
  EXPECT_EQ(optionalNumber(x, t, "speed", 13.9), 13.9);
  EXPECT_EQ(t.attr("speed"), nullptr);
  ASSERT_TRUE(x.next(t));
  EXPECT_TRUE(t.closing);
  EXPECT_FALSE(x.next(t));
}

TEST(Xml, ErrorsNameTheFileAndLineInTheReadersType) {
  EXPECT_EQ(errorOf([] { tagsOf("<a>\n<b x=\"1\"\n"); }), "t.xml:2: unexpected end of file inside <b>");
  EXPECT_EQ(errorOf([] { tagsOf("<a x=1/>"); }), "t.xml:1: attribute 'x' of <a> is not quoted");
  EXPECT_EQ(errorOf([] { tagsOf("\n<a x=\"1\" x=\"2\"/>"); }), "t.xml:2: attribute 'x' of <a> given twice");
  EXPECT_EQ(errorOf([] { tagsOf("<a>\n<!-- open"); }), "t.xml:2: unterminated markup");
  EXPECT_EQ(errorOf([] { tagsOf(std::string("<a>\n\0", 5)); }), "t.xml:2: a NUL byte: not an XML text file");
  EXPECT_EQ(errorOf([] {
              XmlScanner x(std::string("<v speed=\"0x1p3\"/>"), "t.xml", raiseAs<TestError>);
              XmlScanner::Tag t;
              x.next(t);
              required(x, t, "speed");
            }),
            "t.xml:1: <v> attribute 'speed' is not a finite number: '0x1p3'");
  EXPECT_EQ(errorOf([] { XmlScanner x(std::filesystem::path("/nonexistent/t.xml"), raiseAs<TestError>); }),
            "/nonexistent/t.xml: cannot open file");
}

TEST(Xml, BalancedInputHasEveryElementClosedByItsOwnEndTag) {
  // unchecked, a file cut short reads as far as it goes (the SUMO traces' readers say what is missing)
  EXPECT_EQ(tagsOf("<a><b/>"), (std::vector<std::string>{"a", "b/"}));
  EXPECT_EQ(tagsOf("<a><b/></a>", true), (std::vector<std::string>{"a", "b/", "/a"}));
  EXPECT_EQ(errorOf([] { tagsOf("<a>\n<b/>\n", true); }), "t.xml:3: unexpected end of file: <a> (line 1) is not closed");
  EXPECT_EQ(errorOf([] { tagsOf("<a>\n<b>\n</a>", true); }), "t.xml:3: </a> does not close <b> (line 2)");
  EXPECT_EQ(errorOf([] { tagsOf("</a>", true); }), "t.xml:1: </a> closes no open element");
  // depth: the elements around a tag, itself not counted
  XmlScanner x(std::string("<c><s><k/><j></j></s></c>"), "t.xml", raiseAs<TestError>);
  x.requireBalanced();
  XmlScanner::Tag t;
  std::vector<std::size_t> depths;
  while (x.next(t)) depths.push_back(x.depth());
  EXPECT_EQ(depths, (std::vector<std::size_t>{0, 1, 2, 2, 2, 1, 0}));
}

}  // namespace
