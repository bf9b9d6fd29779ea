#include "NameCompleter.hpp"

#include "kerf/document/Document.hpp"

#include <QAbstractItemView>
#include <QCompleter>
#include <QKeyEvent>
#include <QLineEdit>
#include <QStringListModel>

namespace kerf::ui {

namespace {
bool isNameChar(QChar c) { return c.isLetterOrNumber() || c == '_'; }
} // namespace

QStringList parameterNames(const Document& doc)
{
    QStringList names;
    for (const Parameter& p : doc.parameters) names << QString::fromStdString(p.name);
    return names;
}

NameCompleter::NameCompleter(QLineEdit* edit, std::function<QStringList()> names, bool onlyAfterEquals)
    : QObject(edit), edit_(edit), names_(std::move(names)), onlyAfterEquals_(onlyAfterEquals)
{
    model_ = new QStringListModel(this);
    completer_ = new QCompleter(model_, this);
    completer_->setObjectName("nameCompleter");
    completer_->setWidget(edit_); // not setCompleter: that would complete the whole text
    completer_->setCaseSensitivity(Qt::CaseInsensitive);
    completer_->setCompletionMode(QCompleter::PopupCompletion);
    connect(edit_, &QLineEdit::textEdited, this, &NameCompleter::offer);
    connect(completer_, qOverload<const QString&>(&QCompleter::activated), this, &NameCompleter::insert);
    completer_->popup()->installEventFilter(this); // after QCompleter's filter, so it runs first
}

bool NameCompleter::eventFilter(QObject* watched, QEvent* event)
{
    // The Return that picks a name must not also reach the field: QCompleter
    // passes it on by a direct event() call, where the field would commit
    // the expression half typed (a spin box would even put its number back
    // first). This filter sits on the popup in front of QCompleter's own.
    if (watched == completer_->popup() && event->type() == QEvent::KeyPress) {
        const int key = static_cast<QKeyEvent*>(event)->key();
        const QModelIndex chosen = completer_->popup()->currentIndex();
        if ((key == Qt::Key_Return || key == Qt::Key_Enter) && chosen.isValid()) {
            completer_->popup()->hide();
            insert(chosen.data().toString());
            return true;
        }
    }
    return QObject::eventFilter(watched, event);
}

int NameCompleter::wordStart() const
{
    const QString text = edit_->text();
    int start = edit_->cursorPosition();
    while (start > 0 && isNameChar(text[start - 1])) --start;
    return start;
}

void NameCompleter::offer()
{
    const QString text = edit_->text();
    const int start = wordStart();
    const QString prefix = text.mid(start, edit_->cursorPosition() - start);
    // A word being typed, not a number ("18mm") nor a node's field ("seat.size").
    const bool active = (!onlyAfterEquals_ || text.trimmed().startsWith('=')) && !prefix.isEmpty() &&
                        !prefix[0].isDigit() && (start == 0 || text[start - 1] != '.');
    if (!active) {
        completer_->popup()->hide();
        return;
    }
    model_->setStringList(names_());
    completer_->setCompletionPrefix(prefix);
    if (completer_->completionCount() == 0 ||
        (completer_->completionCount() == 1 && completer_->currentCompletion() == prefix)) {
        completer_->popup()->hide();
        return;
    }
    completer_->complete();
    // The first name is chosen: Return takes it (arrows choose another).
    completer_->popup()->setCurrentIndex(completer_->completionModel()->index(0, 0));
}

void NameCompleter::insert(const QString& name)
{
    QString text = edit_->text();
    const int start = wordStart();
    const int end = edit_->cursorPosition();
    text.replace(start, end - start, name);
    edit_->setText(text);
    edit_->setCursorPosition(start + int(name.size()));
    edit_->setModified(true);
}

} // namespace kerf::ui
