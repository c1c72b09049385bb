#include "io/volume/NrrdCompressed.h"

#include <bzlib.h>
#include <zlib.h>

#include <algorithm>
#include <vector>

#include "kernels/base/Error.h"

namespace skelseg::nrrd {

namespace {

constexpr std::uint64_t kMaxDeflateRatio = 1032;
constexpr std::uint64_t kMaxBzip2BlockOutput = 900000 / 5 * 259;
constexpr std::uint64_t kMinBzip2BlockBits = 173;

/// zlib and libbz2 count input and output in unsigned ints.
constexpr std::size_t kMaxPiece = std::size_t(1) << 30;

enum class StepResult { Progress, StreamEnd, Corrupt, OutOfMemory };

/// One zlib inflate stream; 15 + 32 window bits accept gzip and zlib headers.
class GzipStream {
public:
    static constexpr const char* kName = "gzip";

    explicit GzipStream(const std::string& name) {
        if (inflateInit2(&mStream, 15 + 32) != Z_OK)
            throw InputError(name, "cannot initialise zlib");
    }
    ~GzipStream() { inflateEnd(&mStream); }
    GzipStream(const GzipStream&) = delete;
    GzipStream& operator=(const GzipStream&) = delete;

    /// Decompresses from [in, in + inLeft) into [out, out + outLeft) and
    /// advances both.
    StepResult step(const std::uint8_t*& in, std::size_t& inLeft, std::uint8_t*& out,
                    std::size_t& outLeft) {
        mStream.next_in = const_cast<Bytef*>(in);
        mStream.avail_in = uInt(std::min(inLeft, kMaxPiece));
        mStream.next_out = out;
        mStream.avail_out = uInt(std::min(outLeft, kMaxPiece));
        const uInt inBefore = mStream.avail_in;
        const uInt outBefore = mStream.avail_out;
        const int status = inflate(&mStream, Z_NO_FLUSH);
        in += inBefore - mStream.avail_in;
        inLeft -= inBefore - mStream.avail_in;
        out += outBefore - mStream.avail_out;
        outLeft -= outBefore - mStream.avail_out;
        if (status == Z_STREAM_END) return StepResult::StreamEnd;
        if (status == Z_DATA_ERROR || status == Z_NEED_DICT || status == Z_STREAM_ERROR)
            return StepResult::Corrupt;
        if (status == Z_MEM_ERROR) return StepResult::OutOfMemory;
        return StepResult::Progress;
    }

    /// Another gzip member follows the end of this one.
    void restart() { inflateReset(&mStream); }

    std::string corruption() const { return mStream.msg ? mStream.msg : "invalid stream"; }

private:
    z_stream mStream{};
};

class Bzip2Stream {
public:
    static constexpr const char* kName = "bzip2";

    explicit Bzip2Stream(const std::string& name) : mName(name) { start(); }
    ~Bzip2Stream() { BZ2_bzDecompressEnd(&mStream); }
    Bzip2Stream(const Bzip2Stream&) = delete;
    Bzip2Stream& operator=(const Bzip2Stream&) = delete;

    StepResult step(const std::uint8_t*& in, std::size_t& inLeft, std::uint8_t*& out,
                    std::size_t& outLeft) {
        mStream.next_in = const_cast<char*>(reinterpret_cast<const char*>(in));
        mStream.avail_in = unsigned(std::min(inLeft, kMaxPiece));
        mStream.next_out = reinterpret_cast<char*>(out);
        mStream.avail_out = unsigned(std::min(outLeft, kMaxPiece));
        const unsigned inBefore = mStream.avail_in;
        const unsigned outBefore = mStream.avail_out;
        mStatus = BZ2_bzDecompress(&mStream);
        in += inBefore - mStream.avail_in;
        inLeft -= inBefore - mStream.avail_in;
        out += outBefore - mStream.avail_out;
        outLeft -= outBefore - mStream.avail_out;
        if (mStatus == BZ_STREAM_END) return StepResult::StreamEnd;
        if (mStatus == BZ_MEM_ERROR) return StepResult::OutOfMemory;
        if (mStatus != BZ_OK) return StepResult::Corrupt;
        return StepResult::Progress;
    }

    /// libbz2 ends a stream for good; another stream (pbzip2) needs a new one.
    void restart() {
        BZ2_bzDecompressEnd(&mStream);
        start();
    }

    std::string corruption() const {
        if (mStatus == BZ_DATA_ERROR_MAGIC) return "no bzip2 signature 'BZh'";
        if (mStatus == BZ_DATA_ERROR) return "checksum mismatch or invalid block";
        return "invalid stream (libbz2 error " + std::to_string(mStatus) + ")";
    }

private:
    void start() {
        mStream = bz_stream{};
        if (BZ2_bzDecompressInit(&mStream, 0, 0) != BZ_OK)
            throw InputError(mName, "cannot initialise libbz2");
    }

    const std::string& mName;
    bz_stream mStream{};
    int mStatus = BZ_OK;
};

template <typename Stream>
void decompressWith(const std::string& name, const std::uint8_t* data, std::size_t size,
                    DecompressedLength length, ByteSink& sink) {
    Stream stream(name);
    const std::string codec = Stream::kName;
    const bool exact = length.atLeast == length.atMost;
    const auto wanted = [&] {
        return exact ? "the " + std::to_string(length.atMost) + " bytes the header says"
                     : std::to_string(length.atMost) +
                           " bytes: with byte skip -1 the bytes before the samples are at most "
                           "as many as the samples' (or 1 MiB)";
    };
    std::vector<std::uint8_t> chunk(std::size_t(1) << 18);
    std::uint64_t produced = 0;
    for (;;) {
        // Never ask for more than one byte beyond the most allowed: enough
        // to detect "too long" without inflating an unbounded stream.
        const std::size_t room =
            std::size_t(std::min<std::uint64_t>(chunk.size(), length.atMost + 1 - produced));
        std::uint8_t* out = chunk.data();
        std::size_t outLeft = room;
        const std::size_t inBefore = size;
        const StepResult result = stream.step(data, size, out, outLeft);
        const std::size_t got = room - outLeft;
        produced += got;
        if (produced > length.atMost)
            throw InputError(
                name, "data is too long: " + codec + " data decompresses to more than " + wanted());
        sink.append(chunk.data(), got);

        if (result == StepResult::StreamEnd) {
            if (size == 0) break;
            if (exact && produced == length.atMost)
                throw InputError(name, "data is too long: " + std::to_string(size) +
                                           " bytes after the end of the " + codec + " stream");
            stream.restart();  // another member or stream follows
            continue;
        }
        if (result == StepResult::Corrupt)
            throw InputError(name, "corrupt " + codec + " data: " + stream.corruption());
        if (result == StepResult::OutOfMemory)
            throw InputError(name, "out of memory while decompressing " + codec + " data");
        const bool noProgress = got == 0 && size == inBefore;
        // Every sample is there, the stream's end (and its checksum) is not:
        // "truncated after 512 bytes, header says 512" read as a contradiction.
        if (noProgress && size == 0 && produced >= length.atLeast)
            throw InputError(name, "data is too short: the " + codec + " stream is cut off after " +
                                       std::to_string(produced) +
                                       " bytes, before its end and checksum");
        if (noProgress && size == 0)
            throw InputError(name, "data is too short: " + codec + " data is truncated after " +
                                       std::to_string(produced) + " bytes, header says " +
                                       (exact ? "" : "at least ") + std::to_string(length.atLeast));
        if (noProgress)  // the library is stuck: never loop forever on bad input
            throw InputError(name, "corrupt " + codec + " data: decompression makes no progress");
    }
    if (produced < length.atLeast)
        throw InputError(name, "data is too short: " + codec + " data decompresses to " +
                                   std::to_string(produced) + " bytes, header says " +
                                   (exact ? "" : "at least ") + std::to_string(length.atLeast));
}

}  // namespace

std::uint64_t maxDecompressedBytes(Encoding encoding, std::uint64_t size) {
    if (encoding == Encoding::Bzip2)
        return (size * 8 / kMinBzip2BlockBits + 1) * kMaxBzip2BlockOutput;
    return size * kMaxDeflateRatio + 1024;
}

void decompress(const std::string& name, Encoding encoding, const std::uint8_t* data,
                std::size_t size, DecompressedLength length, ByteSink& sink) {
    if (encoding == Encoding::Bzip2)
        decompressWith<Bzip2Stream>(name, data, size, length, sink);
    else
        decompressWith<GzipStream>(name, data, size, length, sink);
}

}  // namespace skelseg::nrrd
