// skelseg: which option texts are decimal numbers.
//
// The command line's numbers are read by CLI11 and std::stod, which also take
// forms nobody types by intent: hexadecimal ("0x30" is 48, "0x1p4" is 16),
// CLI11's octal and binary prefixes ("0o60", "0b110000"), and C's octal
// leading zero ("010" was 8). A value given in one of them was taken without
// a word, so a typo became a different run. The options take decimal text
// only; these are the rules, shared by every option that reads a number.
#pragma once

#include <optional>
#include <string>

namespace skelseg {

/// True for decimal number text: an optional sign, digits with an optional
/// decimal point (or a point and digits), an optional exponent (e3, E-2); and
/// "inf", "infinity" and "nan" in any case, which the options' range checks
/// refuse with their own message.
bool isDecimalNumberText(const std::string& text);

/// The decimal integer text as CLI11 reads it in decimal: an optional sign
/// and digits, leading zeros removed ("048" -> "48", "+7" -> "7",
/// "-0" -> "0"); nullopt for anything else ("0x30", "1e2", "48.0", "").
std::optional<std::string> decimalIntegerText(const std::string& text);

}  // namespace skelseg
