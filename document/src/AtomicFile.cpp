#include "kerf/document/AtomicFile.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace kerf {

namespace {
std::runtime_error ioError(const std::filesystem::path& file, const std::string& what, int err)
{
    return std::runtime_error(file.string() + ": " + what + ": " + std::strerror(err));
}

// Creates a unique temporary file beside `target` and returns its path.
std::filesystem::path makeTemporary(const std::filesystem::path& target)
{
    std::string pattern = (target.parent_path() / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
    if (target.parent_path().empty()) pattern = "." + target.filename().string() + ".tmp-XXXXXX";
    const int fd = ::mkstemp(pattern.data());
    if (fd < 0) throw ioError(target, "cannot create a temporary file beside it", errno);
    ::close(fd);
    return pattern;
}

void syncAndRename(const std::filesystem::path& tmp, const std::filesystem::path& target)
{
    const int fd = ::open(tmp.c_str(), O_RDONLY);
    if (fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
    // Keep the permissions of a file we replace (a user's 0600 file stays 0600).
    std::error_code ec;
    const auto status = std::filesystem::status(target, ec);
    if (!ec && std::filesystem::exists(status))
        std::filesystem::permissions(tmp, status.permissions(), ec);
    else
        std::filesystem::permissions(tmp, std::filesystem::perms(0644), ec);
    if (std::rename(tmp.c_str(), target.c_str()) != 0) throw ioError(target, "cannot replace the file", errno);
}
} // namespace

void writeFileAtomically(const std::filesystem::path& target, const std::function<void(std::ostream&)>& writer)
{
    const auto tmp = makeTemporary(target);
    try {
        {
            std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
            if (!out) throw ioError(target, "cannot write the temporary file", errno);
            writer(out);
            out.flush();
            if (!out) throw ioError(target, "write failed", errno ? errno : EIO);
        }
        syncAndRename(tmp, target);
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw;
    }
}

void writeFileAtomically(const std::filesystem::path& target, std::string_view bytes)
{
    writeFileAtomically(target, [&](std::ostream& out) { out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())); });
}

} // namespace kerf
