#include "io/volume/NrrdIO.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <optional>
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
    /// Fills the `capacity` values from `output` on.
    SampleSink(T* output, std::size_t capacity, SampleType type, bool swapBytes, bool keepValues)
        : mOutput(output),
          mCapacity(capacity),
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

    std::vector<std::uint8_t> take() { return std::move(mBytes); }

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

/// The data of one data file, or what follows an attached header: the
/// file's bytes, and where the samples start after the line skip (and the
/// byte skip, for raw and text data).
struct DataBlock {
    std::string fileBytes;  // a data file's content; empty for attached data
    const std::uint8_t* fileStart = nullptr;
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;
    /// "data file 'NAME': " before a message about one of several data
    /// files; "" where the header names one place of data.
    std::string label;
    std::vector<std::uint8_t> staged;  // decompressed first (bzip2, byte skip -1)
};

/// Runs `step`, putting block.label before the problem of an InputError.
template <typename Step>
void labelled(const std::string& name, const DataBlock& block, Step&& step) {
    if (block.label.empty()) return step();
    try {
        step();
    } catch (const InputError& error) {
        throw InputError(name, block.label + error.problem());
    }
}

/// Everything a block's samples need: checked before the volume is
/// allocated, so that data that cannot hold them allocates nothing.
void checkBlock(const std::string& name, const NrrdHeader& header, DataBlock& block,
                std::uint64_t samples) {
    const Encoding encoding = *header.encoding;
    const std::uint64_t expectedBytes = samples * sampleBytes(*header.type);
    skipLines(name, block.data, block.size, header.lineSkip);
    if (encoding == Encoding::Raw) {
        skipBytes(name, block.data, block.size,
                  header.byteSkip == -1
                      ? std::max<std::uint64_t>(block.size, expectedBytes) - expectedBytes
                      : std::uint64_t(header.byteSkip));
        if (block.size < expectedBytes)
            throw InputError(name, "data is too short: " + std::to_string(block.size) +
                                       " bytes, header says " + std::to_string(expectedBytes));
        if (block.size > expectedBytes)
            throw InputError(name, "data is too long: " + std::to_string(block.size) +
                                       " bytes, header says " + std::to_string(expectedBytes));
        return;
    }
    if (encoding == Encoding::Ascii || encoding == Encoding::Hex) {
        if (header.byteSkip == -1)
            throw InputError(name, std::string("byte skip -1 (the data's last bytes) is not "
                                               "supported for ") +
                                       encodingName(encoding) + " data (raw, gzip and bzip2 only)");
        skipBytes(name, block.data, block.size, std::uint64_t(header.byteSkip));
        const std::uint64_t fewest =
            nrrd::minimumTextBytes(encoding, samples, sampleBytes(*header.type));
        // Ascii is told in numbers, as the decoder tells it, and a short
        // block costs little to count.
        if (block.size < fewest && encoding == Encoding::Ascii)
            throw InputError(name, "data is too short: ascii data has " +
                                       std::to_string(nrrd::countAsciiWords(
                                           reinterpret_cast<const char*>(block.data), block.size)) +
                                       " numbers, header says " + std::to_string(samples));
        if (block.size < fewest)
            throw InputError(name, "data is too short: " + std::to_string(block.size) +
                                       " bytes of " + encodingName(encoding) +
                                       " data cannot hold the " + std::to_string(samples) +
                                       " samples the header says");
        return;
    }
    // gzip and bzip2: teem skips bytes of the decompressed data.
    const std::uint64_t skip = header.byteSkip == -1 ? 0 : std::uint64_t(header.byteSkip);
    if (expectedBytes + skip > nrrd::maxDecompressedBytes(encoding, block.size))
        throw InputError(name, "data is too short: " + std::to_string(block.size) + " bytes of " +
                                   encodingName(encoding) + " data cannot hold the " +
                                   std::to_string(expectedBytes + skip) + " bytes the header says");
}

/// bzip2 expands up to 2 million to 1, and byte skip -1 needs the data's
/// end: such samples are decompressed before the volume is allocated, into
/// memory that grows with what the stream really holds, so that a tiny file
/// claiming gigabytes allocates nothing it cannot fill. Gzip (deflate's
/// bound, 1032:1, keeps the volume in proportion to the file) streams
/// straight into the volume.
bool isStaged(const NrrdHeader& header) {
    const Encoding encoding = *header.encoding;
    return encoding == Encoding::Bzip2 || (encoding == Encoding::Gzip && header.byteSkip == -1);
}

void stageBlock(const std::string& name, const NrrdHeader& header, DataBlock& block,
                std::uint64_t expectedBytes) {
    const bool tail = header.byteSkip == -1;
    const std::uint64_t skip = tail ? 0 : std::uint64_t(header.byteSkip);
    const nrrd::DecompressedLength length{
        expectedBytes + skip,
        tail ? expectedBytes + maxTailPrefix(expectedBytes) : expectedBytes + skip};
    GrowingBuffer decompressed(length.atMost);
    SkipFirstBytes skipping(decompressed, skip);
    nrrd::decompress(name, *header.encoding, block.data, block.size, length, skipping);
    block.staged = decompressed.take();
    // The compressed bytes are done with: no need to hold both.
    std::string().swap(block.fileBytes);
}

/// Decodes a checked (and, if isStaged(), staged) block into `sink`.
template <typename T>
void decodeBlock(const std::string& name, const NrrdHeader& header, const DataBlock& block,
                 std::uint64_t samples, T* output, bool keepValues) {
    const SampleType type = *header.type;
    const Encoding encoding = *header.encoding;
    const std::uint64_t expectedBytes = samples * sampleBytes(type);
    const bool swapBytes = header.bigEndian.value_or(hostIsBigEndian()) != hostIsBigEndian();
    SampleSink<T> sink(output, std::size_t(samples), type,
                       encoding == Encoding::Ascii ? false : swapBytes, keepValues);
    if (isStaged(header)) {
        const std::vector<std::uint8_t>& staged = block.staged;
        sink.append(staged.data() + (staged.size() - expectedBytes), std::size_t(expectedBytes));
    } else if (encoding == Encoding::Raw) {
        sink.append(block.data, block.size);
    } else if (encoding == Encoding::Ascii || encoding == Encoding::Hex) {
        // A block of several data files is named by its label instead.
        const bool namedHere = header.dataFiles.size() == 1 && block.label.empty();
        const nrrd::TextOrigin origin{
            namedHere ? "data file " + quote(header.dataFiles[0]) + ", " : std::string(),
            std::size_t(1 + std::count(block.fileStart, block.data, '\n'))};
        const char* text = reinterpret_cast<const char*>(block.data);
        // Ascii numbers become samples in the host's byte order.
        if (encoding == Encoding::Ascii)
            nrrd::decodeAscii(name, text, block.size, type, samples, origin, sink);
        else
            nrrd::decodeHex(name, text, block.size, expectedBytes, origin, sink);
    } else {
        const std::uint64_t skip = std::uint64_t(header.byteSkip);
        SkipFirstBytes skipping(sink, skip);
        nrrd::decompress(name, encoding, block.data, block.size,
                         {expectedBytes + skip, expectedBytes + skip}, skipping);
    }
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

    // One block for attached data or each data file; several files hold
    // equal runs of the samples (parseNrrdHeader checked that they split).
    const std::size_t blockCount = std::max<std::size_t>(1, header.dataFiles.size());
    const std::uint64_t blockSamples = header.dims.voxelCount() / blockCount;
    std::vector<DataBlock> blocks(blockCount);  // filled in place: no block moves
    if (header.dataFiles.empty()) {
        blocks[0].fileStart = bytes;
        blocks[0].data = bytes + header.dataOffset;
        blocks[0].size = size - header.dataOffset;
    } else if (!headerDirectory) {
        throw InputError(name, "detached header (data file " + quote(*header.dataFileField) +
                                   ") cannot be read from memory");
    }
    // Every file is read and checked before the volume is allocated: the
    // files' bytes are the data a single file would hold.
    for (std::size_t i = 0; i < header.dataFiles.size(); ++i) {
        DataBlock& block = blocks[i];
        const std::string& dataFile = header.dataFiles[i];
        if (header.severalDataFiles) block.label = "data file " + quote(dataFile) + ": ";
        try {
            block.fileBytes = readFileBytes(resolveDataFile(dataFile, *headerDirectory));
        } catch (const InputError& error) {
            throw InputError(name, "data file " + quote(dataFile) + ": " + error.problem());
        }
        block.fileStart = reinterpret_cast<const std::uint8_t*>(block.fileBytes.data());
        block.data = block.fileStart;
        block.size = block.fileBytes.size();
        labelled(name, block, [&] { checkBlock(name, header, block, blockSamples); });
    }
    if (header.dataFiles.empty()) checkBlock(name, header, blocks[0], blockSamples);

    // Before bzip2's staging buffers too: they grow to the samples' bytes.
    if (guards.checkGrid) guards.checkGrid(header.dims);
    const std::uint64_t blockBytes = blockSamples * sampleBytes(type);
    if (isStaged(header))
        for (DataBlock& block : blocks)
            labelled(name, block, [&] { stageBlock(name, header, block, blockBytes); });
    Volume<T> volume(header.dims);
    for (std::size_t i = 0; i < blockCount; ++i)
        labelled(name, blocks[i], [&] {
            decodeBlock(name, header, blocks[i], blockSamples,
                        volume.data() + i * std::size_t(blockSamples), keepValues);
        });
    volume.geometry = header.geometry;
    return volume;
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

std::vector<fs::path> nrrdDetachedDataFiles(const fs::path& header) {
    // A header is text before the data; the first MiB holds any header the
    // readers accept but a long list of data files, and reading no more
    // keeps this cheap on large volumes.
    constexpr std::size_t kHeaderBytes = std::size_t(1) << 20;
    std::string bytes;
    std::vector<fs::path> files;
    try {
        checkReadableFile(header);
        const auto readPrefix = [&](std::size_t limit) {
            std::ifstream in(header, std::ios::binary);
            bytes.resize(limit);
            in.read(bytes.data(), std::streamsize(bytes.size()));
            bytes.resize(std::size_t(in.gcount()));
        };
        readPrefix(kHeaderBytes);
        const auto parse = [&] {
            return nrrd::parseNrrdHeader(
                header.string(), reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
        };
        // A list of data files may go on past the first MiB (a detached
        // header is all header): cut there, the list is too short, or its
        // last name is no file it names. Only a header that starts a list is
        // read further: a large file of anything else (a sparse file of
        // zeros under a NRRD magic) must not be read whole before the
        // memory check refuses it.
        const bool cut = bytes.size() == kHeaderBytes;
        std::optional<nrrd::NrrdHeader> parsed;
        try {
            parsed = parse();
        } catch (const InputError&) {
            if (!cut) throw;
        }
        const bool startsAList = bytes.find("\ndata file: LIST") != std::string::npos ||
                                 bytes.find("\ndatafile: LIST") != std::string::npos;
        if (cut && (!parsed || parsed->severalDataFiles) && startsAList) {
            readPrefix(kMaxNrrdHeaderBytes);
            parsed = parse();
        }
        if (!parsed) return {};
        for (const std::string& dataFile : parsed->dataFiles)
            files.push_back(resolveDataFile(dataFile, directoryOf(header)));
    } catch (const InputError&) {
        return {};
    }
    return files;
}

LabelVolume readNrrdLabels(const fs::path& file) {
    return readNrrdVolumeFile<std::uint16_t>(file, true);
}

LabelVolume readNrrdLabelsFromMemory(const std::string& name, const std::uint8_t* bytes,
                                     std::size_t size) {
    return readNrrdVolume<std::uint16_t>(name, bytes, size, nullptr, true);
}

}  // namespace skelseg
