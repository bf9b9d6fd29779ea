#include "Recovery.hpp"

#include "kerf/document/AtomicFile.hpp"

#include <QDir>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QStandardPaths>
#include <QUuid>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace kerf::ui {

namespace fs = std::filesystem;

std::filesystem::path RecoveryStore::defaultFolder()
{
    const QString overridden = qEnvironmentVariable("KERF_RECOVERY_DIR");
    if (!overridden.isEmpty()) return overridden.toStdString();
    return (QStandardPaths::writableLocation(QStandardPaths::AppDataLocation) + "/recovery").toStdString();
}

RecoveryStore::RecoveryStore(std::filesystem::path folder)
    : folder_(std::move(folder)), session_(QUuid::createUuid().toString(QUuid::WithoutBraces))
{
    std::error_code ec;
    fs::create_directories(folder_, ec);
    lock_ = std::make_unique<QLockFile>(QString::fromStdString(file(session_, ".lock").string()));
    lock_->setStaleLockTime(0); // a lock is stale only when its process is gone
    lock_->tryLock(0);
}

RecoveryStore::~RecoveryStore()
{
    if (abandoned_) return;
    clearAutosave();
    lock_.reset(); // unlocks and removes the lock file
}

std::filesystem::path RecoveryStore::file(const QString& session, const char* suffix) const
{
    return folder_ / (session.toStdString() + suffix);
}

void RecoveryStore::autosave(const Document& doc, const std::optional<std::filesystem::path>& original)
{
    writeFileAtomically(file(session_, ".kerf"), doc.serialize());
    QJsonObject record;
    record["original"] = original ? QString::fromStdString(fs::absolute(*original).string()) : QString();
    record["saved"] = QDateTime::currentDateTimeUtc().toString(Qt::ISODateWithMs);
    writeFileAtomically(file(session_, ".json"), QJsonDocument(record).toJson().toStdString());
}

void RecoveryStore::clearAutosave()
{
    std::error_code ec;
    fs::remove(file(session_, ".json"), ec);
    fs::remove(file(session_, ".kerf"), ec);
}

std::vector<RecoveryCandidate> RecoveryStore::orphans() const
{
    std::vector<RecoveryCandidate> out;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder_, ec)) {
        if (entry.path().extension() != ".json") continue;
        const QString session = QString::fromStdString(entry.path().stem().string());
        if (session == session_) continue;
        // A held lock: that session is running. No lock, or a stale one: it is gone.
        QLockFile other(QString::fromStdString(file(session, ".lock").string()));
        other.setStaleLockTime(0);
        if (!other.tryLock(0)) continue;
        other.unlock();
        RecoveryCandidate c;
        c.session = session;
        c.autosave = file(session, ".kerf");
        if (!fs::exists(c.autosave)) continue;
        std::ifstream in(entry.path());
        std::stringstream text;
        text << in.rdbuf();
        const QJsonObject record = QJsonDocument::fromJson(QByteArray::fromStdString(text.str())).object();
        const QString original = record.value("original").toString();
        if (!original.isEmpty()) c.original = original.toStdString();
        c.savedAt = QDateTime::fromString(record.value("saved").toString(), Qt::ISODateWithMs);
        out.push_back(std::move(c));
    }
    return out;
}

Document RecoveryStore::load(const RecoveryCandidate& c) { return Document::load(c.autosave); }

void RecoveryStore::discard(const RecoveryCandidate& c) const
{
    std::error_code ec;
    fs::remove(c.autosave, ec);
    fs::remove(file(c.session, ".json"), ec);
    fs::remove(file(c.session, ".lock"), ec);
}

void RecoveryStore::abandon()
{
    abandoned_ = true;
    lock_.reset(); // as if the process had died: no lock is held
}

} // namespace kerf::ui
