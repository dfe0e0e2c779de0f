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

// The pieces of s between the separators ("a|b|c" -> a, b, c; "" -> none): views into s.
std::vector<std::string_view> split(std::string_view s, char separator);

// number() for JSON, which has no NaN or infinity: those are written as null.
std::string jsonNumber(double x, int digits = 0);

// Fixed-point text with `decimals` digits after the point (tables, progress lines).
std::string fixed(double x, int decimals);

// One UTF-8 policy for every output (docs/bad_input.md): text read from outside (a scenario's
// name, a SUMO or FCD id) is written as UTF-8, each byte that is not part of a valid UTF-8
// sequence replaced by U+FFFD (as Python's errors="replace" and every browser do), so a JSON, CSV,
// SVG or HTML file is valid UTF-8 whatever its input held. Valid UTF-8 passes unchanged.
bool validUtf8(std::string_view s);
std::string utf8(std::string_view s);

// A JSON string literal: quote, backslash, \n, \r, \t escaped; other control characters as \u00XX;
// invalid UTF-8 as utf8() writes it (valid UTF-8 stays as it is).
std::string jsonString(std::string_view s);

// Text for XML (SVG) content and attribute values: utf8(), '<' '>' '&' '"' as entities, and the
// control characters XML 1.0 forbids (all below 0x20 but tab, LF, CR) as U+FFFD.
std::string xmlText(std::string_view s);

// Text for a terminal line (a name in a progress or summary line): utf8(), control characters
// (ESC and the rest below 0x20, DEL) as \xNN, so no name can move the cursor or retitle the window.
std::string printable(std::string_view s);

// JSON text made safe to place inside an HTML <script> element: '<', '>' and '&' become \u003c,
// \u003e, \u0026 (same value to JSON and JavaScript), so no string in it can close the element
// ("</script>") or open a comment. Outside strings JSON has none of the three.
std::string jsonForScript(std::string_view json);

// A CSV field as RFC 4180 writes it: quoted when it holds a comma, a quote, CR or LF, inner quotes
// doubled; otherwise unchanged. Text is utf8()'s. A field a spreadsheet would take for a formula
// (one beginning '=', '+', '-', '@', tab or CR that is not a number: an id "=HYPERLINK(...)") is
// written with a leading apostrophe, as OWASP advises; a number ("-3.5") is left alone, and a
// field that begins with an apostrophe before such text gets one more, so csvFields reads every
// field back as it was.
std::string csvField(std::string_view s);

// The fields of one CSV line as csvField wrote them: quoted fields unquoted, inner quotes undoubled,
// the formula guard's apostrophe removed (the reader's half of csvField; a line holds no line
// break outside quotes).
std::vector<std::string> csvFields(std::string_view line);

// The text on one line: CR and LF become spaces (a message in a table cell that is read line by line).
std::string oneLine(std::string_view s);

}  // namespace st::io
