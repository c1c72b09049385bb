#include "engine/NumberText.h"

#include <algorithm>
#include <cctype>

namespace skelseg {

namespace {

bool isDigit(char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
}

}  // namespace

bool isDecimalNumberText(const std::string& text) {
    std::size_t i = 0;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    std::string word = text.substr(i);
    std::transform(word.begin(), word.end(), word.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (word == "inf" || word == "infinity" || word == "nan") return true;
    std::size_t digits = 0;
    while (i < text.size() && isDigit(text[i])) ++i, ++digits;
    if (i < text.size() && text[i] == '.') {
        ++i;
        while (i < text.size() && isDigit(text[i])) ++i, ++digits;
    }
    if (digits == 0) return false;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
        std::size_t exponentDigits = 0;
        while (i < text.size() && isDigit(text[i])) ++i, ++exponentDigits;
        if (exponentDigits == 0) return false;
    }
    return i == text.size();
}

std::optional<std::string> decimalIntegerText(const std::string& text) {
    std::size_t i = 0;
    const bool negative = !text.empty() && text[0] == '-';
    if (!text.empty() && (text[0] == '+' || text[0] == '-')) i = 1;
    if (i == text.size() || !std::all_of(text.begin() + std::ptrdiff_t(i), text.end(), isDigit))
        return std::nullopt;
    const std::size_t firstNonZero = text.find_first_not_of('0', i);
    if (firstNonZero == std::string::npos) return std::string("0");
    return (negative ? "-" : "") + text.substr(firstNonZero);
}

}  // namespace skelseg
