#include "NameCompleter.hpp"

#include "kerf/document/Document.hpp"
#include "kerf/document/ReferableNumbers.hpp"

#include <algorithm>

#include <QAbstractItemView>
#include <QCompleter>
#include <QKeyEvent>
#include <QLineEdit>
#include <QScrollBar>
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

QStringList parameterAndFeatureNames(const Document& doc)
{
    QStringList names = parameterNames(doc);
    for (const std::string& ref : referableNumbers(doc)) names << QString::fromStdString(ref);
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
    // Anywhere in the name: "=left" finds "stile-left.size[0]" (the tree shows
    // the feature as "Left stile").
    completer_->setFilterMode(Qt::MatchContains);
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
    // A feature's number is longer: its id may hold '-', then '.', a path and
    // indices ("stile-left.size[0]"). That word, where some name holds it
    // ("depth-thi" is a subtraction, and the shorter word is completed).
    int wide = edit_->cursorPosition();
    while (wide > 0 && (isNameChar(text[wide - 1]) || QStringLiteral("-.[]").contains(text[wide - 1]))) --wide;
    if (wide < start) {
        const QString longer = text.mid(wide, edit_->cursorPosition() - wide);
        for (const QString& name : names_())
            if (name.contains(longer, Qt::CaseInsensitive)) return wide;
    }
    return start;
}

void NameCompleter::offer()
{
    const QString text = edit_->text();
    const int start = wordStart();
    const QString prefix = text.mid(start, edit_->cursorPosition() - start);
    // A word being typed, not a number ("18mm") nor a node's field ("seat.size").
    const bool active = (!onlyAfterEquals_ || text.trimmed().startsWith('=')) && !prefix.isEmpty() &&
                        !prefix[0].isDigit() && (start == 0 || text[start - 1] != '.') && !prefix.contains(']');
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
    // As wide as the longest name offered ("panel-groove.transform.translate[2]"
    // was cut off at the field's width), at least the field's.
    QAbstractItemView* popup = completer_->popup();
    const int wide = popup->sizeHintForColumn(0) + popup->verticalScrollBar()->sizeHint().width() + 12;
    completer_->complete(QRect(0, 0, std::max(edit_->width(), wide), edit_->height()));
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
