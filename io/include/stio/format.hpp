#pragma once
// Output text shared by every writer: numbers, JSON string literals, CSV fields. One function per
// job, so two files never disagree on how a value is written.
#include <string>
#include <string_view>
#include <vector>

namespace st::io {

// A double as text. digits == 0: the shortest form (at least 6 significant digits tried first)
// that reads back to the same double; digits > 0: printf's %.<digits>g. NaN is "nan", infinities
// "inf" and "-inf".
std::string number(double x, int digits = 0);

// number() for JSON, which has no NaN or infinity: those are written as null.
std::string jsonNumber(double x, int digits = 0);

// Fixed-point text with `decimals` digits after the point (tables, progress lines).
std::string fixed(double x, int decimals);

// A JSON string literal: quote, backslash, \n, \r, \t escaped; other control characters as \u00XX.
// Bytes >= 0x80 pass through (UTF-8 stays UTF-8).
std::string jsonString(std::string_view s);

// JSON text made safe to place inside an HTML <script> element: '<', '>' and '&' become \u003c,
// \u003e, \u0026 (same value to JSON and JavaScript), so no string in it can close the element
// ("</script>") or open a comment. Outside strings JSON has none of the three.
std::string jsonForScript(std::string_view json);

// A CSV field as RFC 4180 writes it: quoted when it holds a comma, a quote, CR or LF, inner quotes
// doubled; otherwise unchanged.
std::string csvField(std::string_view s);

// The fields of one CSV line as csvField wrote them: quoted fields unquoted, inner quotes undoubled
// (the reader's half of csvField; a line holds no line break outside quotes).
std::vector<std::string> csvFields(std::string_view line);

// The text on one line: CR and LF become spaces (a message in a table cell that is read line by line).
std::string oneLine(std::string_view s);

}  // namespace st::io
