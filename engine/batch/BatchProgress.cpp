#include "engine/batch/BatchProgress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "kernels/base/Error.h"

namespace skelseg {

std::string formatDuration(double seconds) {
    const long total = std::lround(std::max(0.0, seconds));
    char text[32];
    if (total >= 3600)
        std::snprintf(text, sizeof text, "%ldh%02ldm", total / 3600, total % 3600 / 60);
    else if (total >= 60)
        std::snprintf(text, sizeof text, "%ldm%02lds", total / 60, total % 60);
    else
        std::snprintf(text, sizeof text, "%lds", total);
    return text;
}

BatchProgress::BatchProgress(std::size_t total, std::size_t skipped, Display display,
                             std::FILE* stream)
    : mDisplay(display),
      mStream(stream),
      mStart(std::chrono::steady_clock::now()),
      mTotal(total),
      mFinished(skipped) {
    if (mDisplay == Display::Auto)
        mDisplay = ::isatty(::fileno(stream)) ? Display::Bar : Display::Lines;
    const std::lock_guard<std::mutex> lock(mMutex);
    if (mDisplay == Display::Bar) drawBarLocked();
}

BatchProgress::~BatchProgress() {
    const std::lock_guard<std::mutex> lock(mMutex);
    if (mBarVisible) {
        drawBarLocked();
        std::fputc('\n', mStream);
        mBarVisible = false;
    }
}

double BatchProgress::elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
}

std::string BatchProgress::statusText() const {
    const std::lock_guard<std::mutex> lock(mMutex);
    return statusTextLocked();
}

std::string BatchProgress::statusTextLocked() const {
    const double minutes = elapsedSeconds() / 60.0;
    const double rate = minutes > 0 ? double(mSegmented) / minutes : 0.0;
    char text[160];
    const std::string eta =
        rate > 0 ? formatDuration(double(mTotal - mFinished) / rate * 60.0) : std::string("?");
    std::snprintf(text, sizeof text, "%zu/%zu shapes, %.1f shapes/min, ETA %s", mFinished, mTotal,
                  rate, eta.c_str());
    return text;
}

void BatchProgress::clearBarLocked() {
    if (mBarVisible) std::fputs("\r\033[K", mStream);
    mBarVisible = false;
}

void BatchProgress::drawBarLocked() {
    constexpr int kWidth = 30;
    const double fraction = mTotal ? double(mFinished) / double(mTotal) : 1.0;
    const int filled = int(fraction * kWidth);
    std::string bar(std::size_t(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(mStream, "\r\033[Kbatch [%s] %s", bar.c_str(), statusTextLocked().c_str());
    std::fflush(mStream);
    mBarVisible = true;
}

void BatchProgress::shapeFinished(const BatchEntry& entry) {
    const std::lock_guard<std::mutex> lock(mMutex);
    ++mFinished;
    if (entry.status == "done") ++mSegmented;
    const bool failed = entry.status == "failed";
    // Quiet: the caller lists the failures at the end.
    if (mDisplay == Display::Quiet) return;
    clearBarLocked();
    // The name is the input's file name: it may hold a newline.
    const std::string name = escapeControlCharacters(entry.name);
    if (failed)
        std::fprintf(mStream, "skelseg batch: %s failed: %s\n",
                     escapeControlCharacters(nameAndLine(entry)).c_str(),
                     escapeControlCharacters(entry.error).c_str());
    else if (mDisplay == Display::Lines)
        std::fprintf(mStream, "skelseg batch: [%s] %s: %llu parts, %.2f s\n",
                     statusTextLocked().c_str(), name.c_str(),
                     static_cast<unsigned long long>(entry.parts), entry.wallSeconds);
    if (mDisplay == Display::Bar) drawBarLocked();
    std::fflush(mStream);
}

void BatchProgress::message(const std::string& line) {
    const std::lock_guard<std::mutex> lock(mMutex);
    const bool redraw = mBarVisible;
    clearBarLocked();
    std::fprintf(mStream, "%s\n", escapeControlCharacters(line).c_str());
    if (redraw) drawBarLocked();
    std::fflush(mStream);
}

}  // namespace skelseg
