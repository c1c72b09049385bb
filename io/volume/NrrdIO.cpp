#include "io/volume/NrrdIO.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "io/files/TextFile.h"
#include "io/volume/NrrdHeader.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;

namespace skelseg {

namespace {

using nrrd::Encoding;
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
class SampleSink {
public:
    SampleSink(Volume<T>& volume, SampleType type, bool swapBytes, bool keepValues)
        : mOutput(volume.data()),
          mCapacity(volume.size()),
          mType(type),
          mSampleBytes(sampleBytes(type)),
          mSwap(swapBytes),
          mKeepValues(keepValues) {}

    void append(const std::uint8_t* bytes, std::size_t count) {
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
        switch (mType) {
            case SampleType::Int8:
                convertAs<std::int8_t>(bytes, count);
                break;
            case SampleType::UInt8:
                convertAs<std::uint8_t>(bytes, count);
                break;
            case SampleType::Int16:
                convertAs<std::int16_t>(bytes, count);
                break;
            case SampleType::UInt16:
                convertAs<std::uint16_t>(bytes, count);
                break;
            case SampleType::Int32:
                convertAs<std::int32_t>(bytes, count);
                break;
            case SampleType::UInt32:
                convertAs<std::uint32_t>(bytes, count);
                break;
            case SampleType::Int64:
                convertAs<std::int64_t>(bytes, count);
                break;
            case SampleType::UInt64:
                convertAs<std::uint64_t>(bytes, count);
                break;
            case SampleType::Float:
                convertAs<float>(bytes, count);
                break;
            case SampleType::Double:
                convertAs<double>(bytes, count);
                break;
        }
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

/// Deflate cannot expand more than 1032:1, so a stream of N bytes never
/// inflates to more than about 1032*N. Used to reject a header that claims
/// more data than the file can hold before allocating the volume.
constexpr std::uint64_t kMaxDeflateRatio = 1032;

/// Passes on what follows the first `skip` bytes it receives.
template <typename Sink>
class SkipFirstBytes {
public:
    SkipFirstBytes(Sink& sink, std::uint64_t skip) : mSink(sink), mLeft(skip) {}

    void append(const std::uint8_t* bytes, std::size_t count) {
        const std::size_t dropped = std::size_t(std::min<std::uint64_t>(mLeft, count));
        mLeft -= dropped;
        mSink.append(bytes + dropped, count - dropped);
    }

private:
    Sink& mSink;
    std::uint64_t mLeft;
};

template <typename Sink>
void inflateSamples(const std::string& name, const std::uint8_t* data, std::size_t size,
                    std::uint64_t expectedBytes, Sink& sink) {
    z_stream stream{};
    // 15 + 32: accept both gzip and zlib headers.
    if (inflateInit2(&stream, 15 + 32) != Z_OK) throw InputError(name, "cannot initialise zlib");
    struct StreamGuard {
        z_stream* stream;
        ~StreamGuard() { inflateEnd(stream); }
    } guard{&stream};

    std::vector<std::uint8_t> chunk(std::size_t(1) << 18);
    std::size_t consumed = 0;  // input bytes handed to zlib so far
    std::uint64_t produced = 0;
    const auto feed = [&] {
        if (stream.avail_in == 0 && consumed < size) {
            const std::size_t piece = std::min<std::size_t>(size - consumed, 1u << 30);
            stream.next_in = const_cast<Bytef*>(data + consumed);
            stream.avail_in = uInt(piece);
            consumed += piece;
        }
    };
    for (;;) {
        feed();
        // Never ask for more than one byte beyond the expected count: enough
        // to detect "too long" without inflating an unbounded stream.
        const std::uint64_t room = expectedBytes + 1 - produced;
        stream.next_out = chunk.data();
        stream.avail_out = uInt(std::min<std::uint64_t>(chunk.size(), room));
        const uInt inputBefore = stream.avail_in;
        const int status = inflate(&stream, Z_NO_FLUSH);
        const std::size_t got = std::size_t(stream.next_out - chunk.data());
        produced += got;
        if (produced > expectedBytes)
            throw InputError(name, "data is too long: gzip data decompresses to more than the " +
                                       std::to_string(expectedBytes) + " bytes the header says");
        sink.append(chunk.data(), got);

        if (status == Z_STREAM_END) {
            const std::size_t remaining = stream.avail_in + (size - consumed);
            if (remaining == 0) break;
            if (produced == expectedBytes)
                throw InputError(name, "data is too long: " + std::to_string(remaining) +
                                           " bytes after the end of the gzip stream");
            inflateReset(&stream);  // another gzip member follows
            continue;
        }
        if (status == Z_DATA_ERROR || status == Z_NEED_DICT || status == Z_STREAM_ERROR)
            throw InputError(name, std::string("corrupt gzip data: ") +
                                       (stream.msg ? stream.msg : "invalid stream"));
        if (status == Z_MEM_ERROR)
            throw InputError(name, "out of memory while decompressing gzip data");
        const bool noProgress = got == 0 && stream.avail_in == inputBefore;
        if (noProgress && stream.avail_in == 0 && consumed == size)
            throw InputError(name, "data is too short: gzip data is truncated after " +
                                       std::to_string(produced) + " bytes, header says " +
                                       std::to_string(expectedBytes));
        if (noProgress && stream.avail_in > 0)  // zlib is stuck: never loop forever on bad input
            throw InputError(name, "corrupt gzip data: decompression makes no progress");
    }
    if (produced < expectedBytes)
        throw InputError(name, "data is too short: gzip data decompresses to " +
                                   std::to_string(produced) + " bytes, header says " +
                                   std::to_string(expectedBytes));
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
                         const fs::path* headerDirectory, bool keepValues) {
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

    const std::uint64_t expectedBytes = header.dims.voxelCount() * sampleBytes(type);
    const bool swapBytes = header.bigEndian.value_or(hostIsBigEndian()) != hostIsBigEndian();
    if (*header.encoding == Encoding::Raw) {
        const std::uint64_t skip =
            header.byteSkip == -1 ? std::max<std::uint64_t>(dataSize, expectedBytes) - expectedBytes
                                  : std::uint64_t(header.byteSkip);
        if (skip > dataSize)
            throw InputError(name, "data is too short: byte skip " + std::to_string(skip) +
                                       " is past the " + std::to_string(dataSize) +
                                       " bytes of data");
        data += skip;
        dataSize -= std::size_t(skip);
        if (dataSize < expectedBytes)
            throw InputError(name, "data is too short: " + std::to_string(dataSize) +
                                       " bytes, header says " + std::to_string(expectedBytes));
        if (dataSize > expectedBytes)
            throw InputError(name, "data is too long: " + std::to_string(dataSize) +
                                       " bytes, header says " + std::to_string(expectedBytes));
        Volume<T> volume(header.dims);
        SampleSink<T> sink(volume, type, swapBytes, keepValues);
        sink.append(data, dataSize);
        volume.geometry = header.geometry;
        return volume;
    }
    if (header.byteSkip == -1)
        throw InputError(name,
                         "byte skip -1 (the data's last bytes) is supported for raw data "
                         "only, not gzip");
    // teem skips the bytes of the decompressed data.
    const std::uint64_t skip = std::uint64_t(header.byteSkip);
    if (expectedBytes + skip > std::uint64_t(dataSize) * kMaxDeflateRatio + 1024)
        throw InputError(name, "data is too short: " + std::to_string(dataSize) +
                                   " bytes of gzip data cannot hold the " +
                                   std::to_string(expectedBytes + skip) + " bytes the header says");
    Volume<T> volume(header.dims);
    SampleSink<T> sink(volume, type, swapBytes, keepValues);
    SkipFirstBytes<SampleSink<T>> skipping(sink, skip);
    inflateSamples(name, data, dataSize, expectedBytes + skip, skipping);
    volume.geometry = header.geometry;
    return volume;
}

template <typename T>
Volume<T> readNrrdVolumeFile(const fs::path& file, bool keepValues) {
    const std::string bytes = readFileBytes(file);
    const fs::path directory = directoryOf(file);
    return readNrrdVolume<T>(file.string(), reinterpret_cast<const std::uint8_t*>(bytes.data()),
                             bytes.size(), &directory, keepValues);
}

}  // namespace

MaskVolume readNrrdMask(const fs::path& file) {
    return readNrrdVolumeFile<std::uint8_t>(file, false);
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
