// skelseg: the one text tokenizer of the hand-written readers.
//
// Walks a text buffer without copying, either line by line (OFF, OBJ, the
// PLY header) or token by token across lines (ASCII STL, ASCII PLY data), and
// counts line numbers for error messages. The two modes may be mixed: a token
// read after a line starts on the next line.
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "io/files/TextFile.h"

namespace skelseg {

class TextTokenizer {
public:
    TextTokenizer(const char* data, std::size_t size) : mText(data, size) {}
    explicit TextTokenizer(std::string_view text) : mText(text) {}

    /// Next line without its terminator and, when stripComments, without a
    /// '#' comment. False at the end of the buffer.
    bool nextLine(std::string_view& line, bool stripComments) {
        const bool afterNewline = mAtLineEnd && mPosition < mText.size();
        if (mPosition + (afterNewline ? 1 : 0) >= mText.size()) return false;
        if (afterNewline) {
            ++mPosition;  // the previous line's '\n'
            ++mLineNumber;
        }
        std::size_t end = mText.find('\n', mPosition);
        if (end == std::string_view::npos) end = mText.size();
        line = mText.substr(mPosition, end - mPosition);
        mPosition = end;
        mAtLineEnd = true;
        if (stripComments) {
            const std::size_t hash = line.find('#');
            if (hash != std::string_view::npos) line = line.substr(0, hash);
        }
        return true;
    }

    /// Next line holding a token (comments and blank lines skipped).
    bool nextSignificantLine(std::string_view& line) {
        while (nextLine(line, true))
            for (char c : line)
                if (!isBlank(c)) return true;
        return false;
    }

    /// Next whitespace-separated token, empty at the end of the buffer.
    std::string_view nextToken() noexcept {
        mAtLineEnd = false;
        while (mPosition < mText.size() && isSpace(mText[mPosition])) {
            if (mText[mPosition] == '\n') ++mLineNumber;
            ++mPosition;
        }
        const std::size_t begin = mPosition;
        while (mPosition < mText.size() && !isSpace(mText[mPosition])) ++mPosition;
        return mText.substr(begin, mPosition - begin);
    }

    /// Skips the rest of the current line (the next token starts below it).
    void skipLine() noexcept {
        while (mPosition < mText.size() && mText[mPosition] != '\n') ++mPosition;
    }

    /// 1-based number of the line the last line or token came from.
    std::size_t lineNumber() const noexcept { return mLineNumber; }

    /// Bytes after the last line or token read (a line's '\n' not counted).
    std::size_t bytesLeft() const noexcept {
        const std::size_t position = mPosition + (mAtLineEnd && mPosition < mText.size() ? 1 : 0);
        return mText.size() - position;
    }

private:
    std::string_view mText;
    std::size_t mPosition = 0;
    std::size_t mLineNumber = 1;
    bool mAtLineEnd = false;  // mPosition is on the '\n' of the line just returned
};

/// A decimal integer with an optional '+', and nothing else.
inline bool parseInteger(std::string_view token, std::int64_t& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
    return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

/// A real number (from_chars syntax, also "inf" and "nan") with an optional
/// '+', and nothing else.
inline bool parseReal(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
    return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

}  // namespace skelseg
