#include "engine/python/ArrayMask.h"

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>

#include "kernels/base/Error.h"
#include "kernels/base/ParallelFor.h"

namespace skelseg {

namespace {

// Loads go through memcpy: numpy arrays need not be aligned.
template <typename Bits>
Bits load(const std::uint8_t* p) noexcept {
    Bits value;
    std::memcpy(&value, p, sizeof value);
    return value;
}

// Integers and bools are nonzero when any byte is, in either byte order.
template <typename Bits>
struct IntegerElement {
    static bool isObject(const std::uint8_t* p) noexcept { return load<Bits>(p) != 0; }
    static bool isNan(const std::uint8_t*) noexcept { return false; }
};

template <typename Real>
struct RealElement {
    static bool isObject(const std::uint8_t* p) noexcept { return load<Real>(p) != Real(0); }
    static bool isNan(const std::uint8_t* p) noexcept { return std::isnan(load<Real>(p)); }
};

// IEEE half precision from its bits: no arithmetic type for it in C++17.
struct HalfElement {
    static bool isObject(const std::uint8_t* p) noexcept {
        return (load<std::uint16_t>(p) & 0x7fffu) != 0;  // -0 is zero
    }
    static bool isNan(const std::uint8_t* p) noexcept {
        const std::uint16_t bits = load<std::uint16_t>(p);
        return (bits & 0x7c00u) == 0x7c00u && (bits & 0x03ffu) != 0;
    }
};

template <typename Function>
auto withElement(const ArrayView& array, Function&& function) {
    switch (array.element) {
        case MaskElement::Float16:
            return function(HalfElement{});
        case MaskElement::Float32:
            return function(RealElement<float>{});
        case MaskElement::Float64:
            return function(RealElement<double>{});
        case MaskElement::Integer:
            break;
    }
    switch (array.itemSize) {
        case 1:
            return function(IntegerElement<std::uint8_t>{});
        case 2:
            return function(IntegerElement<std::uint16_t>{});
        case 4:
            return function(IntegerElement<std::uint32_t>{});
        case 8:
            return function(IntegerElement<std::uint64_t>{});
        default:
            throw UsageError("mask elements of " + std::to_string(array.itemSize) +
                             " bytes are not supported");
    }
}

const std::uint8_t* elementAt(const ArrayView& a, std::int64_t x, std::int64_t y,
                              std::int64_t z) noexcept {
    return a.data + x * a.strides[0] + y * a.strides[1] + z * a.strides[2];
}

// The NaN with the smallest z, then y, then x: the same one whatever the
// threads, so the message does not change from run to run.
[[noreturn]] void throwFirstNan(const ArrayView& a, std::int64_t z, const std::string& name) {
    withElement(a, [&](auto element) {
        for (std::int64_t y = 0; y < a.shape[1]; ++y)
            for (std::int64_t x = 0; x < a.shape[0]; ++x)
                if (element.isNan(elementAt(a, x, y, z)))
                    throw InputError(name, "NaN at index [" + std::to_string(x) + ", " +
                                               std::to_string(y) + ", " + std::to_string(z) +
                                               "] (nonzero is object; NaN is neither)");
        return 0;
    });
    throw InputError(name, "NaN in slice " + std::to_string(z));
}

void recordNanSlice(std::atomic<std::int64_t>& first, std::int64_t z) noexcept {
    std::int64_t seen = first.load();
    while (z < seen && !first.compare_exchange_weak(seen, z)) {
    }
}

}  // namespace

std::uint64_t countObjectVoxels(const ArrayView& a, const std::string& name, bool threaded) {
    std::atomic<std::uint64_t> total{0};
    std::atomic<std::int64_t> firstNanSlice{std::numeric_limits<std::int64_t>::max()};
    withElement(a, [&](auto element) {
        parallelFor(
            a.shape[2],
            [&](std::int64_t zBegin, std::int64_t zEnd) {
                std::uint64_t count = 0;
                for (std::int64_t z = zBegin; z < zEnd; ++z) {
                    bool nan = false;
                    for (std::int64_t y = 0; y < a.shape[1]; ++y)
                        for (std::int64_t x = 0; x < a.shape[0]; ++x) {
                            const std::uint8_t* p = elementAt(a, x, y, z);
                            count += element.isObject(p);
                            nan |= element.isNan(p);
                        }
                    if (nan) recordNanSlice(firstNanSlice, z);
                }
                total += count;
            },
            threaded);
        return 0;
    });
    if (firstNanSlice.load() != std::numeric_limits<std::int64_t>::max())
        throwFirstNan(a, firstNanSlice.load(), name);
    return total.load();
}

MaskVolume maskFromArray(const ArrayView& a, const std::string& name, bool threaded) {
    const Dims dims = Dims::checked(a.shape[0], a.shape[1], a.shape[2], name);
    MaskVolume mask(dims);
    std::atomic<std::int64_t> firstNanSlice{std::numeric_limits<std::int64_t>::max()};
    withElement(a, [&](auto element) {
        parallelFor(
            a.shape[2],
            [&](std::int64_t zBegin, std::int64_t zEnd) {
                for (std::int64_t z = zBegin; z < zEnd; ++z) {
                    bool nan = false;
                    for (std::int64_t y = 0; y < a.shape[1]; ++y) {
                        std::uint8_t* out = &mask(0, int(y), int(z));
                        for (std::int64_t x = 0; x < a.shape[0]; ++x) {
                            const std::uint8_t* p = elementAt(a, x, y, z);
                            out[x] = element.isObject(p) ? 1 : 0;
                            nan |= element.isNan(p);
                        }
                    }
                    if (nan) recordNanSlice(firstNanSlice, z);
                }
            },
            threaded);
        return 0;
    });
    if (firstNanSlice.load() != std::numeric_limits<std::int64_t>::max())
        throwFirstNan(a, firstNanSlice.load(), name);
    return mask;
}

}  // namespace skelseg
