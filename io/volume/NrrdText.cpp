#include "io/volume/NrrdText.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>
#include <type_traits>

#include "io/files/TextFile.h"
#include "io/files/TextTokenizer.h"
#include "kernels/base/Error.h"

namespace skelseg::nrrd {

namespace {

/// Collects decoded bytes and passes them on in blocks, not one sample at a time.
class BlockWriter {
public:
    explicit BlockWriter(ByteSink& sink) : mSink(sink) {}

    void put(const std::uint8_t* bytes, std::size_t count) {
        if (mFilled + count > sizeof(mBlock)) flush();
        std::memcpy(mBlock + mFilled, bytes, count);
        mFilled += count;
    }

    void flush() {
        mSink.append(mBlock, mFilled);
        mFilled = 0;
    }

private:
    ByteSink& mSink;
    std::uint8_t mBlock[4096] = {};
    std::size_t mFilled = 0;
};

std::string where(const TextOrigin& origin, std::size_t line) {
    return origin.source + "line " + std::to_string(line);
}

enum class Parsed { Ok, NotANumber, NotAnInteger, OutOfRange };

/// An integer sample: an integer literal, or any real number of integer value.
template <typename Sample>
Parsed parseIntegerSample(std::string_view token, Sample& sample) {
    using Limits = std::numeric_limits<Sample>;
    if constexpr (std::is_unsigned_v<Sample>) {
        std::string_view digits = token;
        if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
        std::uint64_t value = 0;
        const auto result = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (!digits.empty() && result.ptr == digits.data() + digits.size()) {
            if (result.ec == std::errc::result_out_of_range || value > Limits::max())
                return Parsed::OutOfRange;
            if (result.ec == std::errc()) {
                sample = Sample(value);
                return Parsed::Ok;
            }
        }
    } else {
        std::int64_t value = 0;
        if (parseInteger(token, value)) {
            if (value < std::int64_t(Limits::min()) || value > std::int64_t(Limits::max()))
                return Parsed::OutOfRange;
            sample = Sample(value);
            return Parsed::Ok;
        }
    }
    double real = 0.0;
    if (!parseReal(token, real)) return Parsed::NotANumber;
    if (!std::isfinite(real) || real != std::floor(real)) return Parsed::NotAnInteger;
    // double(max) + 1 is exact for up to 32 bits and rounds to 2^64 or 2^63 above.
    if (real < double(Limits::min()) || real >= double(Limits::max()) + 1.0)
        return Parsed::OutOfRange;
    sample = Sample(real);
    return Parsed::Ok;
}

template <typename Sample>
Parsed parseSample(std::string_view token, Sample& sample) {
    if constexpr (std::is_floating_point_v<Sample>) {
        double real = 0.0;
        if (!parseReal(token, real)) return Parsed::NotANumber;
        sample = Sample(real);
        return Parsed::Ok;
    } else {
        return parseIntegerSample(token, sample);
    }
}

constexpr bool isAsciiSeparator(char c) {
    return isSpace(c) || c == ',';
}

}  // namespace

std::uint64_t countAsciiWords(const char* text, std::size_t size) {
    std::uint64_t words = 0;
    bool inWord = false;
    for (std::size_t i = 0; i < size; ++i) {
        const bool separator = isAsciiSeparator(text[i]);
        if (!separator && !inWord) ++words;
        inWord = !separator;
    }
    return words;
}

namespace {

template <typename Sample>
void decodeAsciiAs(const std::string& name, const char* text, std::size_t size, SampleType type,
                   std::uint64_t samples, const TextOrigin& origin, ByteSink& sink) {
    BlockWriter writer(sink);
    std::uint64_t count = 0;
    std::size_t line = origin.firstLine;
    std::size_t i = 0;
    for (;;) {
        while (i < size && isAsciiSeparator(text[i])) {
            if (text[i] == '\n') ++line;
            ++i;
        }
        if (i == size) break;
        const std::size_t begin = i;
        while (i < size && !isAsciiSeparator(text[i])) ++i;
        const std::string_view token(text + begin, i - begin);
        if (count == samples)
            throw InputError(name, "data is too long: ascii data has more than the " +
                                       std::to_string(samples) + " numbers the header says (" +
                                       quote(token) + " on " + where(origin, line) + ")");
        Sample sample{};
        const Parsed parsed = parseSample(token, sample);
        if (parsed != Parsed::Ok) {
            const std::string what = parsed == Parsed::NotANumber     ? "is not a number"
                                     : parsed == Parsed::NotAnInteger ? "is not an integer"
                                                                      : "is out of range";
            throw InputError(name, "ascii data, " + where(origin, line) + ": " + quote(token) +
                                       " " + what + " (sample " + std::to_string(count + 1) +
                                       ", type " + sampleTypeName(type) + ")");
        }
        std::uint8_t bytes[sizeof(Sample)];
        std::memcpy(bytes, &sample, sizeof(Sample));
        writer.put(bytes, sizeof(Sample));
        ++count;
    }
    if (count < samples)
        throw InputError(name, "data is too short: ascii data has " + std::to_string(count) +
                                   " numbers, header says " + std::to_string(samples));
    writer.flush();
}

int hexValue(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

}  // namespace

std::uint64_t minimumTextBytes(Encoding encoding, std::uint64_t samples, std::size_t sampleSize) {
    if (encoding == Encoding::Hex) return 2 * samples * sampleSize;
    return 2 * samples - 1;
}

void decodeAscii(const std::string& name, const char* text, std::size_t size, SampleType type,
                 std::uint64_t samples, const TextOrigin& origin, ByteSink& sink) {
    visitSampleType(type, [&](auto zero) {
        decodeAsciiAs<decltype(zero)>(name, text, size, type, samples, origin, sink);
    });
}

void decodeHex(const std::string& name, const char* text, std::size_t size, std::uint64_t bytes,
               const TextOrigin& origin, ByteSink& sink) {
    BlockWriter writer(sink);
    std::uint64_t decoded = 0;
    std::uint64_t digits = 0;
    int high = 0;
    std::size_t line = origin.firstLine;
    for (std::size_t i = 0; i < size; ++i) {
        const char c = text[i];
        if (isSpace(c)) {
            if (c == '\n') ++line;
            continue;
        }
        const int value = hexValue(c);
        if (value < 0)
            throw InputError(name, "hex data, " + where(origin, line) + ": " +
                                       quote(std::string_view(&text[i], 1)) +
                                       " is not a hex digit");
        if (decoded == bytes)
            throw InputError(name, "data is too long: hex data has more than the " +
                                       std::to_string(bytes) + " bytes the header says (" +
                                       where(origin, line) + ")");
        ++digits;
        if (digits % 2 == 1) {
            high = value;
            continue;
        }
        const std::uint8_t byte = std::uint8_t(high * 16 + value);
        writer.put(&byte, 1);
        ++decoded;
    }
    if (digits % 2 == 1)
        throw InputError(name, "data is too short: hex data ends in the middle of a byte (" +
                                   std::to_string(digits) +
                                   " hex digits, an odd number); header "
                                   "says " +
                                   std::to_string(bytes) + " bytes");
    if (decoded < bytes)
        throw InputError(name, "data is too short: hex data has " + std::to_string(decoded) +
                                   " bytes, header says " + std::to_string(bytes));
    writer.flush();
}

}  // namespace skelseg::nrrd
