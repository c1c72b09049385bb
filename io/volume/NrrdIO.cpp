#include "io/volume/NrrdIO.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "io/files/TextFile.h"
#include "io/volume/NrrdCompressed.h"
#include "io/volume/NrrdHeader.h"
#include "io/volume/NrrdText.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

using nrrd::ByteSink;
using nrrd::Encoding;
using nrrd::encodingName;
using nrrd::hostIsBigEndian;
using nrrd::NrrdHeader;
using nrrd::parseNrrdHeader;
using nrrd::sampleBytes;
using nrrd::SampleType;
using nrrd::sampleTypeName;

// ---------------------------------------------------------------------------
// Sample decoding
// ---------------------------------------------------------------------------

template <typename Sample>
Sample loadSample(const std::uint8_t* bytes, bool swapBytes) {
    std::uint8_t buffer[sizeof(Sample)];
    std::memcpy(buffer, bytes, sizeof(Sample));
    if (swapBytes) std::reverse(buffer, buffer + sizeof(Sample));
    Sample sample;
    std::memcpy(&sample, buffer, sizeof(Sample));
    return sample;
}

/// Receives the sample bytes in any chunking (gzip output arrives in pieces
/// that need not end on a sample boundary) and converts them into the
/// volume, in file order.
template <typename T>
class SampleSink final : public ByteSink {
public:
    SampleSink(Volume<T>& volume, SampleType type, bool swapBytes, bool keepValues)
        : mOutput(volume.data()),
          mCapacity(volume.size()),
          mType(type),
          mSampleBytes(sampleBytes(type)),
          mSwap(swapBytes),
          mKeepValues(keepValues) {}

    void append(const std::uint8_t* bytes, std::size_t count) override {
        if (mPartialCount > 0) {
            // The sizeof bound is implied by mSampleBytes <= 8; spelled out for the compiler.
            const std::size_t take =
                std::min({count, mSampleBytes - mPartialCount, sizeof(mPartial) - mPartialCount});
            std::memcpy(mPartial + mPartialCount, bytes, take);
            mPartialCount += take;
            bytes += take;
            count -= take;
            if (mPartialCount < mSampleBytes) return;
            convert(mPartial, 1);
            mPartialCount = 0;
        }
        const std::size_t whole = count / mSampleBytes;
        convert(bytes, whole);
        bytes += whole * mSampleBytes;
        count -= whole * mSampleBytes;
        mPartialCount = std::min(count, sizeof(mPartial));
        std::memcpy(mPartial, bytes, mPartialCount);
    }

private:
    void convert(const std::uint8_t* bytes, std::size_t count) {
        if (count > mCapacity - mWritten) throw std::logic_error("NRRD sample sink overflow");
        nrrd::visitSampleType(mType, [&](auto zero) { convertAs<decltype(zero)>(bytes, count); });
        mWritten += count;
    }

    template <typename Sample>
    void convertAs(const std::uint8_t* bytes, std::size_t count) {
        T* out = mOutput + mWritten;
        if (mKeepValues) {
            for (std::size_t i = 0; i < count; ++i)
                out[i] = T(loadSample<Sample>(bytes + i * sizeof(Sample), mSwap));
        } else {
            // NaN compares unequal to zero, so a NaN sample counts as object.
            for (std::size_t i = 0; i < count; ++i)
                out[i] = loadSample<Sample>(bytes + i * sizeof(Sample), mSwap) != Sample(0) ? T(1)
                                                                                            : T(0);
        }
    }

    T* mOutput;
    std::size_t mCapacity;
    std::size_t mWritten = 0;
    SampleType mType;
    std::size_t mSampleBytes;
    bool mSwap;
    bool mKeepValues;
    std::uint8_t mPartial[8] = {};
    std::size_t mPartialCount = 0;
};

/// Passes on what follows the first `skip` bytes it receives.
class SkipFirstBytes final : public ByteSink {
public:
    SkipFirstBytes(ByteSink& sink, std::uint64_t skip) : mSink(sink), mLeft(skip) {}

    void append(const std::uint8_t* bytes, std::size_t count) override {
        const std::size_t dropped = std::size_t(std::min<std::uint64_t>(mLeft, count));
        mLeft -= dropped;
        mSink.append(bytes + dropped, count - dropped);
    }

private:
    ByteSink& mSink;
    std::uint64_t mLeft;
};

/// Keeps what it receives, growing with the data but never past `limit`
/// bytes of capacity: memory follows what the stream really holds, not
/// what its header claims.
class GrowingBuffer final : public ByteSink {
public:
    explicit GrowingBuffer(std::uint64_t limit) : mLimit(limit) {}

    void append(const std::uint8_t* bytes, std::size_t count) override {
        const std::size_t needed = mBytes.size() + count;
        if (needed > mBytes.capacity())
            mBytes.reserve(std::size_t(std::max<std::uint64_t>(
                needed, std::min<std::uint64_t>(2 * std::uint64_t(mBytes.capacity()), mLimit))));
        mBytes.insert(mBytes.end(), bytes, bytes + count);
    }

    const std::vector<std::uint8_t>& bytes() const { return mBytes; }

private:
    std::uint64_t mLimit;
    std::vector<std::uint8_t> mBytes;
};

/// The part before the samples that byte skip -1 allows in compressed data,
/// which must be decompressed to its end to find its last bytes: as many
/// bytes as the samples (or 1 MiB), so that a stream of any length is not
/// decompressed without end.
std::uint64_t maxTailPrefix(std::uint64_t sampleBytes) {
    return std::max<std::uint64_t>(sampleBytes, std::uint64_t(1) << 20);
}

/// Skips `lines` lines ('\n'-terminated) at the start of the data.
void skipLines(const std::string& name, const std::uint8_t*& data, std::size_t& dataSize,
               std::int64_t lines) {
    for (std::int64_t line = 0; line < lines; ++line) {
        const void* newline = std::memchr(data, '\n', dataSize);
        if (!newline)
            throw InputError(name, "data is too short: line skip " + std::to_string(lines) +
                                       " passes the end of the data after " + std::to_string(line) +
                                       " lines");
        const std::size_t length =
            std::size_t(static_cast<const std::uint8_t*>(newline) - data) + 1;
        data += length;
        dataSize -= length;
    }
}

/// Skips `skip` bytes of the (raw or text) data.
void skipBytes(const std::string& name, const std::uint8_t*& data, std::size_t& dataSize,
               std::uint64_t skip) {
    if (skip > dataSize)
        throw InputError(name, "data is too short: byte skip " + std::to_string(skip) +
                                   " is past the " + std::to_string(dataSize) + " bytes of data");
    data += skip;
    dataSize -= std::size_t(skip);
}

/// A detached header's data file: relative names are relative to the header.
fs::path resolveDataFile(const std::string& dataFile, const fs::path& headerDirectory) {
    const fs::path dataPath(dataFile);
    return dataPath.is_relative() ? headerDirectory / dataPath : dataPath;
}

fs::path directoryOf(const fs::path& file) {
    return file.has_parent_path() ? file.parent_path() : fs::path(".");
}

template <typename T>
Volume<T> readNrrdVolume(const std::string& name, const std::uint8_t* bytes, std::size_t size,
                         const fs::path* headerDirectory, bool keepValues,
                         const VolumeReadGuards& guards = {}) {
    const NrrdHeader header = parseNrrdHeader(name, bytes, size);
    const SampleType type = *header.type;
    if (keepValues && type != SampleType::UInt8 && type != SampleType::UInt16)
        throw InputError(name,
                         std::string("labels must be uint8 or uint16 samples, file has type ") +
                             sampleTypeName(type));

    const std::uint8_t* data = bytes + header.dataOffset;
    std::size_t dataSize = size - header.dataOffset;
    std::string detachedBytes;
    if (header.dataFile) {
        if (!headerDirectory)
            throw InputError(name, "detached header (data file " + quote(*header.dataFile) +
                                       ") cannot be read from memory");
        const fs::path dataPath = resolveDataFile(*header.dataFile, *headerDirectory);
        try {
            detachedBytes = readFileBytes(dataPath);
        } catch (const InputError& error) {
            throw InputError(name, "data file " + quote(*header.dataFile) + ": " + error.problem());
        }
        data = reinterpret_cast<const std::uint8_t*>(detachedBytes.data());
        dataSize = detachedBytes.size();
    }

    // teem skips the lines of the data file, or of what follows an attached
    // header, for every encoding, and then the byte skip.
    const std::uint8_t* const fileStart =
        header.dataFile ? reinterpret_cast<const std::uint8_t*>(detachedBytes.data()) : bytes;
    skipLines(name, data, dataSize, header.lineSkip);

    const Encoding encoding = *header.encoding;
    const std::uint64_t samples = header.dims.voxelCount();
    const std::uint64_t expectedBytes = samples * sampleBytes(type);
    const bool swapBytes = header.bigEndian.value_or(hostIsBigEndian()) != hostIsBigEndian();
    const auto finish = [&](Volume<T>& volume) {
        volume.geometry = header.geometry;
        return std::move(volume);
    };
    if (encoding == Encoding::Raw) {
        skipBytes(name, data, dataSize,
                  header.byteSkip == -1
                      ? std::max<std::uint64_t>(dataSize, expectedBytes) - expectedBytes
                      : std::uint64_t(header.byteSkip));
        if (dataSize < expectedBytes)
            throw InputError(name, "data is too short: " + std::to_string(dataSize) +
                                       " bytes, header says " + std::to_string(expectedBytes));
        if (dataSize > expectedBytes)
            throw InputError(name, "data is too long: " + std::to_string(dataSize) +
                                       " bytes, header says " + std::to_string(expectedBytes));
        if (guards.checkGrid) guards.checkGrid(header.dims);
        Volume<T> volume(header.dims);
        SampleSink<T> sink(volume, type, swapBytes, keepValues);
        sink.append(data, dataSize);
        return finish(volume);
    }

    if (encoding == Encoding::Ascii || encoding == Encoding::Hex) {
        if (header.byteSkip == -1)
            throw InputError(name, std::string("byte skip -1 (the data's last bytes) is not "
                                               "supported for ") +
                                       encodingName(encoding) + " data (raw, gzip and bzip2 only)");
        skipBytes(name, data, dataSize, std::uint64_t(header.byteSkip));
        const std::uint64_t fewest = nrrd::minimumTextBytes(encoding, samples, sampleBytes(type));
        // Refused before the volume is allocated; ascii is told in numbers,
        // as the decoder tells it, and a short block costs little to count.
        if (dataSize < fewest && encoding == Encoding::Ascii)
            throw InputError(name, "data is too short: ascii data has " +
                                       std::to_string(nrrd::countAsciiWords(
                                           reinterpret_cast<const char*>(data), dataSize)) +
                                       " numbers, header says " + std::to_string(samples));
        if (dataSize < fewest)
            throw InputError(name, "data is too short: " + std::to_string(dataSize) + " bytes of " +
                                       encodingName(encoding) + " data cannot hold the " +
                                       std::to_string(samples) + " samples the header says");
        if (guards.checkGrid) guards.checkGrid(header.dims);
        const nrrd::TextOrigin origin{
            header.dataFile ? "data file " + quote(*header.dataFile) + ", " : std::string(),
            std::size_t(1 + std::count(fileStart, data, '\n'))};
        const char* text = reinterpret_cast<const char*>(data);
        Volume<T> volume(header.dims);
        if (encoding == Encoding::Ascii) {
            // The numbers become samples in the host's byte order.
            SampleSink<T> sink(volume, type, false, keepValues);
            nrrd::decodeAscii(name, text, dataSize, type, samples, origin, sink);
        } else {
            SampleSink<T> sink(volume, type, swapBytes, keepValues);
            nrrd::decodeHex(name, text, dataSize, expectedBytes, origin, sink);
        }
        return finish(volume);
    }

    // gzip and bzip2: teem skips bytes of the decompressed data.
    const bool tail = header.byteSkip == -1;
    const std::uint64_t skip = tail ? 0 : std::uint64_t(header.byteSkip);
    const nrrd::DecompressedLength length{
        expectedBytes + skip,
        tail ? expectedBytes + maxTailPrefix(expectedBytes) : expectedBytes + skip};
    if (expectedBytes + skip > nrrd::maxDecompressedBytes(encoding, dataSize))
        throw InputError(name, "data is too short: " + std::to_string(dataSize) + " bytes of " +
                                   encodingName(encoding) + " data cannot hold the " +
                                   std::to_string(expectedBytes + skip) + " bytes the header says");
    // Before bzip2's staging buffer too: it grows to the samples' bytes.
    if (guards.checkGrid) guards.checkGrid(header.dims);
    if (encoding == Encoding::Gzip && !tail) {
        // Deflate's bound (1032:1) keeps the volume allocated here in
        // proportion to the file; the samples stream straight into it.
        Volume<T> volume(header.dims);
        SampleSink<T> sink(volume, type, swapBytes, keepValues);
        SkipFirstBytes skipping(sink, skip);
        nrrd::decompress(name, encoding, data, dataSize, length, skipping);
        return finish(volume);
    }
    // bzip2 expands up to 2 million to 1, and byte skip -1 needs the data's
    // end: the samples are decompressed first, into memory that grows with
    // what the stream really holds, so that a tiny file claiming gigabytes
    // allocates nothing it cannot fill.
    GrowingBuffer decompressed(length.atMost);
    SkipFirstBytes skipping(decompressed, skip);
    nrrd::decompress(name, encoding, data, dataSize, length, skipping);
    const std::vector<std::uint8_t>& staged = decompressed.bytes();
    Volume<T> volume(header.dims);
    SampleSink<T> sink(volume, type, swapBytes, keepValues);
    sink.append(staged.data() + (staged.size() - expectedBytes), std::size_t(expectedBytes));
    return finish(volume);
}

template <typename T>
Volume<T> readNrrdVolumeFile(const fs::path& file, bool keepValues,
                             const VolumeReadGuards& guards = {}) {
    const std::string bytes = readFileBytes(file);
    const fs::path directory = directoryOf(file);
    return readNrrdVolume<T>(file.string(), reinterpret_cast<const std::uint8_t*>(bytes.data()),
                             bytes.size(), &directory, keepValues, guards);
}

}  // namespace

MaskVolume readNrrdMask(const fs::path& file, const VolumeReadGuards& guards) {
    return readNrrdVolumeFile<std::uint8_t>(file, false, guards);
}

MaskVolume readNrrdMaskFromMemory(const std::string& name, const std::uint8_t* bytes,
                                  std::size_t size) {
    return readNrrdVolume<std::uint8_t>(name, bytes, size, nullptr, false);
}

std::optional<fs::path> nrrdDetachedDataFile(const fs::path& header) {
    // A header is text before the data; the first MiB holds any header the
    // readers accept, and reading no more keeps this cheap on large volumes.
    constexpr std::size_t kHeaderBytes = std::size_t(1) << 20;
    std::string bytes;
    try {
        checkReadableFile(header);
        std::ifstream in(header, std::ios::binary);
        bytes.resize(kHeaderBytes);
        in.read(bytes.data(), std::streamsize(bytes.size()));
        bytes.resize(std::size_t(in.gcount()));
        const nrrd::NrrdHeader parsed = nrrd::parseNrrdHeader(
            header.string(), reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
        if (!parsed.dataFile) return std::nullopt;
        return resolveDataFile(*parsed.dataFile, directoryOf(header));
    } catch (const InputError&) {
        return std::nullopt;
    }
}

LabelVolume readNrrdLabels(const fs::path& file) {
    return readNrrdVolumeFile<std::uint16_t>(file, true);
}

LabelVolume readNrrdLabelsFromMemory(const std::string& name, const std::uint8_t* bytes,
                                     std::size_t size) {
    return readNrrdVolume<std::uint16_t>(name, bytes, size, nullptr, true);
}

}  // namespace skelseg
