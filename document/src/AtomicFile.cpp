#include "kerf/document/AtomicFile.hpp"

#include "kerf/document/FileKind.hpp"
#include "kerf/document/PrintableText.hpp"

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <random>
#include <streambuf>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace kerf {

namespace fs = std::filesystem;

namespace {

OutputFileError refusal(const fs::path& file, const std::string& why)
{
    return OutputFileError(printable(file.string(), 400) + ": " + why);
}

OutputFileError ioError(const fs::path& file, const std::string& what, int err)
{
    return refusal(file, what + ": " + std::strerror(err));
}

// A temporary file's name beside `file`: ".NAME.tmp-XXXXXX".
fs::path temporaryName(const fs::path& file)
{
    static constexpr char kChars[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    thread_local std::mt19937_64 rng{std::random_device{}()};
    std::string suffix(6, 'x');
    for (char& c : suffix) c = kChars[rng() % (sizeof kChars - 1)];
    return file.parent_path() / ("." + file.filename().string() + ".tmp-" + suffix);
}

std::string folderOf(const fs::path& file) { return file.has_parent_path() ? file.parent_path().string() : "."; }

// Why a folder takes no new file, in the words of the person who chose it
// (a newcomer who typed /proc/x.stl was told "cannot create a temporary
// file beside it", which is how the file is written, not what is wrong).
OutputFileError folderRefuses(const fs::path& file, int err)
{
    const std::string folder = "the folder '" + printable(folderOf(file)) + "'";
    std::string why;
    switch (err) {
    case EACCES:
    case EPERM: why = "you may not create files in " + folder; break;
    case EROFS: why = folder + " is on a read-only disk"; break;
    case ENOSPC:
    case EDQUOT: why = "the disk of " + folder + " is full"; break;
    // "No such file or directory" about a folder that exists (a virtual
    // one, such as /proc) only confused a newcomer: no reason then.
    case ENOENT: why = folder + " takes no new files"; break;
    default: why = folder + " takes no new files (" + std::strerror(err) + ")"; break;
    }
    return refusal(file, why + "; choose another folder; nothing was written");
}

// Creates a new temporary file beside `file` with mode 0666 less the umask
// (O_EXCL: never an existing file, never through a link). Returns its fd.
int createTemporary(const fs::path& file, fs::path& name)
{
    for (int attempt = 0; attempt < 100; ++attempt) {
        name = temporaryName(file);
        const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0666);
        if (fd >= 0) return fd;
        if (errno != EEXIST) throw folderRefuses(file, errno);
    }
    throw ioError(file, "cannot create a temporary file beside it", EEXIST);
}

// A std::ostream's buffer over a file descriptor, so that the bytes go to
// exactly the file created above.
class DescriptorBuffer : public std::streambuf {
public:
    explicit DescriptorBuffer(int fd) : fd_(fd) { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
    int error() const { return error_; }

protected:
    int_type overflow(int_type c) override
    {
        if (!flushBuffer()) return traits_type::eof();
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(c);
            pbump(1);
        }
        return traits_type::not_eof(c);
    }
    int sync() override { return flushBuffer() ? 0 : -1; }
    // Writers that go back to patch what they wrote (a ZIP's local headers:
    // lib3mf's 3MF) seek the file itself, after what is buffered is written.
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override
    {
        if (!(which & std::ios_base::out) || !flushBuffer()) return pos_type(off_type(-1));
        const int whence = dir == std::ios_base::beg ? SEEK_SET : dir == std::ios_base::cur ? SEEK_CUR : SEEK_END;
        const off_t at = ::lseek(fd_, off_t(off), whence);
        if (at < 0) {
            error_ = errno;
            return pos_type(off_type(-1));
        }
        return pos_type(off_type(at));
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override
    {
        return seekoff(off_type(pos), std::ios_base::beg, which);
    }

private:
    bool flushBuffer()
    {
        const char* p = pbase();
        while (p < pptr()) {
            const ssize_t n = ::write(fd_, p, std::size_t(pptr() - p));
            if (n < 0) {
                if (errno == EINTR) continue;
                error_ = errno;
                return false;
            }
            p += n;
        }
        setp(buffer_.data(), buffer_.data() + buffer_.size());
        return true;
    }

    int fd_;
    int error_ = 0;
    std::array<char, 1 << 16> buffer_{};
};

// Holds SIGINT, SIGTERM and SIGHUP while a file is written, where they would
// kill the process (their default action): the first one is remembered and
// raised again once the temporary file is gone. Where the program handles
// them itself (kerf export's cancellation, for one), they are left alone.
// Writes on several threads at once share one hold: the first installs it,
// the last releases it (and raises what arrived meanwhile).
std::atomic<int> deferredSignal{0};
extern "C" void deferSignal(int sig)
{
    int none = 0;
    deferredSignal.compare_exchange_strong(none, sig);
}

class HeldSignals {
public:
    HeldSignals()
    {
        const std::lock_guard lock(mutex_);
        if (holders_++ > 0) return;
        deferredSignal = 0;
        for (std::size_t i = 0; i < kSignals.size(); ++i) {
            struct sigaction current {};
            held_[i] = ::sigaction(kSignals[i], nullptr, &current) == 0 && current.sa_handler == SIG_DFL;
            if (!held_[i]) continue;
            struct sigaction defer {};
            defer.sa_handler = deferSignal;
            sigemptyset(&defer.sa_mask);
            ::sigaction(kSignals[i], &defer, &previous_[i]);
        }
    }
    ~HeldSignals() { release(); }
    HeldSignals(const HeldSignals&) = delete;
    HeldSignals& operator=(const HeldSignals&) = delete;

    bool interrupted() const { return deferredSignal != 0; }

    // Once per hold: the last writer restores the dispositions and raises a
    // held signal (which, by default, ends the process).
    void release()
    {
        if (released_) return;
        released_ = true;
        int sig = 0;
        {
            const std::lock_guard lock(mutex_);
            if (--holders_ > 0) return;
            for (std::size_t i = 0; i < kSignals.size(); ++i)
                if (held_[i]) ::sigaction(kSignals[i], &previous_[i], nullptr);
            sig = deferredSignal.exchange(0);
        }
        if (sig) ::raise(sig);
    }

private:
    static constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};
    static inline std::mutex mutex_;
    static inline int holders_ = 0;
    static inline std::array<bool, 3> held_{};
    static inline std::array<struct sigaction, 3> previous_{};
    bool released_ = false;
};

} // namespace

fs::path checkOutputFile(const fs::path& target)
{
    if (target.empty()) throw OutputFileError("the output file name is empty");
    fs::path file = target;
    struct stat st {};
    if (::lstat(target.c_str(), &st) == 0) {
        if (S_ISLNK(st.st_mode)) {
            struct stat pointed {};
            if (::stat(target.c_str(), &pointed) != 0)
                throw refusal(target, errno == ENOENT ? "is a symbolic link to nothing; nothing was written"
                                                      : "is a symbolic link that cannot be followed (" +
                                                            std::string(std::strerror(errno)) + "); nothing was written");
            if (!S_ISREG(pointed.st_mode))
                throw refusal(target, "is a symbolic link to " + describeFileKind(pointed.st_mode) +
                                          ", not to a regular file; nothing was written");
            std::error_code ec;
            file = fs::canonical(target, ec);
            if (ec) throw ioError(target, "cannot follow the symbolic link", ec.value());
        } else if (!S_ISREG(st.st_mode)) {
            throw refusal(target, "is " + describeFileKind(st.st_mode) + ", not a regular file; nothing was written");
        }
    } else if (errno != ENOENT) {
        throw ioError(target, "cannot use it as an output file", errno);
    }
    if (file.filename().empty()) throw refusal(target, "names a folder, not a file; nothing was written");

    // The folder must exist and take new files: try it.
    const std::string folder = folderOf(file);
    struct stat fst {};
    if (::stat(folder.c_str(), &fst) != 0)
        throw refusal(target, "the folder '" + printable(folder) + "' does not exist; nothing was written");
    if (!S_ISDIR(fst.st_mode))
        throw refusal(target, "'" + printable(folder) + "' is " + describeFileKind(fst.st_mode) +
                                  ", not a folder; nothing was written");
    fs::path probe;
    const int fd = createTemporary(file, probe);
    ::close(fd);
    ::unlink(probe.c_str());
    return file;
}

void writeFileAtomically(const fs::path& target, const std::function<void(std::ostream&)>& writer)
{
    const fs::path file = checkOutputFile(target);
    HeldSignals held;
    fs::path tmp;
    const int fd = createTemporary(file, tmp);
    bool open = true;
    try {
        DescriptorBuffer buffer(fd);
        std::ostream out(&buffer);
        writer(out);
        out.flush();
        if (!out || buffer.error()) throw ioError(target, "write failed", buffer.error() ? buffer.error() : EIO);
        if (held.interrupted()) throw refusal(target, "interrupted; nothing was written");
        // A file we replace keeps its permissions (a user's 0600 file stays
        // 0600); a new one keeps the umask's.
        struct stat old {};
        if (::stat(file.c_str(), &old) == 0 && S_ISREG(old.st_mode)) ::fchmod(fd, old.st_mode & 07777);
        if (::fsync(fd) != 0 && errno != EINVAL) throw ioError(target, "cannot flush the file to disk", errno);
        open = false;
        if (::close(fd) != 0) throw ioError(target, "write failed", errno);
    } catch (...) {
        if (open) ::close(fd);
        std::error_code ec;
        fs::remove(tmp, ec);
        held.release();
        throw;
    }
    // The target may have been replaced by something else while we wrote.
    try {
        struct stat now {};
        if (::lstat(file.c_str(), &now) == 0 && !S_ISREG(now.st_mode))
            throw refusal(target, "became " + describeFileKind(now.st_mode) + " while it was written; nothing was written");
        if (held.interrupted()) throw refusal(target, "interrupted; nothing was written");
        if (std::rename(tmp.c_str(), file.c_str()) != 0) throw ioError(target, "cannot replace the file", errno);
    } catch (...) {
        std::error_code ec;
        fs::remove(tmp, ec);
        held.release();
        throw;
    }
    held.release();
}

void writeFileAtomically(const fs::path& target, std::string_view bytes)
{
    writeFileAtomically(target, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

} // namespace kerf
