#include "io/files/OffKeyword.h"

#include <string>

#include "io/files/TextFile.h"

namespace skelseg {

std::size_t offKeywordEnd(std::string_view token) {
    const std::string lower = lowercase(token);
    for (std::size_t end = lower.size(); end >= 3; --end) {
        if (lower.compare(end - 3, 3, "off") != 0) continue;
        for (std::size_t i = end; i < lower.size(); ++i)
            if (lower[i] < '0' || lower[i] > '9') return 0;
        return end;
    }
    return 0;
}

bool isOffKeywordPrefix(std::string_view prefix) {
    for (char c : prefix)
        if (c != 'S' && c != 'T' && c != 'C' && c != 'N' && c != '4' && c != 'n') return false;
    return true;
}

bool isOffKeyword(std::string_view token) {
    const std::size_t end = offKeywordEnd(token);
    return end != 0 && isOffKeywordPrefix(token.substr(0, end - 3));
}

}  // namespace skelseg
