#include "DocumentFile.hpp"

#include "kerf/document/DocumentError.hpp"
#include "kerf/document/FileKind.hpp"
#include "kerf/document/Limits.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace kerf::detail {

namespace {

class FileDescriptor {
public:
    explicit FileDescriptor(int fd) : fd_(fd) {}
    ~FileDescriptor()
    {
        if (fd_ >= 0) ::close(fd_);
    }
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    int get() const { return fd_; }

private:
    int fd_;
};

std::string mebibytes(std::uint64_t bytes)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / double(1 << 20));
    return buf;
}

} // namespace

std::string readDocumentFile(const std::filesystem::path& file)
{
    const std::string name = file.string();
    auto refuse = [&](const std::string& why) -> DocumentError { return DocumentError(name, "", "", why); };
    if (name.empty()) throw refuse("the file name is empty: name a Kerf document (FILE.kerf)");
    // O_NONBLOCK: opening a FIFO that no one writes to would otherwise wait
    // for a writer forever. Cleared below for reading.
    const FileDescriptor fd(::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY));
    if (fd.get() < 0) {
        const int why = errno;
        if (why == EISDIR) throw refuse("is a folder, not a Kerf document");
        // A socket cannot be opened: said by what it is, not by errno's words.
        struct stat kind {};
        if (::stat(file.c_str(), &kind) == 0 && S_ISSOCK(kind.st_mode))
            throw refuse("is " + describeFileKind(kind.st_mode) + ", not a Kerf document file");
        throw refuse("cannot open the file: " + std::string(std::strerror(why)));
    }
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0) throw refuse("cannot read the file: " + std::string(std::strerror(errno)));
    if (S_ISDIR(st.st_mode)) throw refuse("is a folder, not a Kerf document");
    if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode))
        throw refuse("is " + describeFileKind(st.st_mode) + ", not a Kerf document file");
    if (S_ISREG(st.st_mode) && std::uint64_t(st.st_size) > limits::kMaxDocumentBytes)
        throw refuse("is too large: " + mebibytes(std::uint64_t(st.st_size)) + "; a Kerf document may have at most " +
                     std::to_string(limits::kMaxDocumentBytes >> 20) + " MiB");
    const int flags = ::fcntl(fd.get(), F_GETFL);
    if (flags >= 0) ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK);

    std::string text;
    if (S_ISREG(st.st_mode)) text.reserve(std::size_t(st.st_size));
    char buffer[1 << 16];
    for (;;) {
        const ssize_t got = ::read(fd.get(), buffer, sizeof buffer);
        if (got < 0) {
            if (errno == EINTR) continue;
            throw refuse("cannot read the file: " + std::string(std::strerror(errno)));
        }
        if (got == 0) break;
        if (text.size() + std::size_t(got) > limits::kMaxDocumentBytes)
            throw refuse("is too large: more than " + std::to_string(limits::kMaxDocumentBytes >> 20) +
                         " MiB, the most a Kerf document may have");
        text.append(buffer, std::size_t(got));
    }
    return text;
}

} // namespace kerf::detail
