#pragma once
// Autosave and crash recovery. Each running session keeps, in a recovery
// folder, a lock file (held while it runs, QLockFile), a copy of its
// document written atomically at every autosave, and a small JSON record
// (the document's own path, when it was saved). A clean exit removes all
// three. At start-up, a record whose session holds no lock (it crashed, or
// was killed) is offered for recovery; one whose lock is held belongs to
// another running Kerf and is left alone.
//
// The folder is the platform's application data folder + "/recovery"
// (KERF_RECOVERY_DIR overrides it, for tests).

#include "kerf/document/Document.hpp"

#include <QDateTime>
#include <QLockFile>
#include <QString>

#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

namespace kerf::ui {

struct RecoveryCandidate {
    QString session;                                 // id of the session that left it
    std::filesystem::path autosave;                  // the autosaved document
    std::optional<std::filesystem::path> original;   // the file it was opened from, if any
    QDateTime savedAt;
};

class RecoveryStore {
public:
    /// Starts this session's record in `folder` (created when missing).
    explicit RecoveryStore(std::filesystem::path folder = defaultFolder());
    ~RecoveryStore();

    static std::filesystem::path defaultFolder();

    /// Writes `doc` (as JSON, even if it would not validate) as this
    /// session's autosave, atomically. Throws std::runtime_error naming the file.
    void autosave(const Document& doc, const std::optional<std::filesystem::path>& original);
    /// Removes this session's autosave (the document was saved or closed clean).
    void clearAutosave();

    /// Autosaves left by sessions that are no longer running.
    std::vector<RecoveryCandidate> orphans() const;
    /// Loads a candidate's document (throws DocumentError when it is unreadable).
    static Document load(const RecoveryCandidate& c);
    /// Deletes a candidate's files (after it was restored or declined).
    void discard(const RecoveryCandidate& c) const;

    /// For tests: ends the session as a crash would, leaving the autosave
    /// and record behind with no lock.
    void abandon();

    const std::filesystem::path& folder() const { return folder_; }
    const QString& session() const { return session_; }

private:
    std::filesystem::path file(const QString& session, const char* suffix) const;

    std::filesystem::path folder_;
    QString session_;
    std::unique_ptr<QLockFile> lock_;
    bool abandoned_ = false;
};

} // namespace kerf::ui
