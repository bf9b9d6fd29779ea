#include "QuantityEdit.hpp"

#include "LengthDisplay.hpp"
#include "NameCompleter.hpp"
#include "UndoKeysToWindow.hpp"

#include <QLineEdit>
#include <QRegularExpression>
#include <QSignalBlocker>
#include <QKeyEvent>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>

namespace kerf::ui {

QuantityEdit::QuantityEdit(Unit unit, QWidget* parent) : QDoubleSpinBox(parent), unit_(unit)
{
    // Wide ranges: the document's validation, not the widget, says what is
    // allowed, and says why, quoting what was typed (a range of 1e9 quoted
    // a typed 1e30 as "is 1000000000 mm").
    setRange(-1e100, 1e100);
    setDecimals(6);
    setSingleStep(1.0);
    setKeyboardTracking(false); // typed text commits on Enter or leaving the field
    setAccelerated(true);
    setSuffix(unitSuffix());
    if (unit_ == Unit::Length) {
        followLengthDisplay();
        connect(&LengthDisplay::instance(), &LengthDisplay::changed, this, &QuantityEdit::followLengthDisplay);
    }
    setCorrectionMode(QAbstractSpinBox::CorrectToPreviousValue);
    connect(lineEdit(), &QLineEdit::editingFinished, this, [this] {
        lineEdit()->setModified(false); // committed: Ctrl+Z now undoes the edit (UndoKeysToWindow)
    });
    UndoKeysToWindow::install(lineEdit(), this);
    // An expression begun over a number has no unit after it: the field
    // showed "=apron_h - 20 mm" while it was typed, as if the mm were part
    // of it (the unit comes back with the number, showEnteredText).
    connect(lineEdit(), &QLineEdit::textEdited, this, [this](const QString& text) {
        if (!text.trimmed().startsWith('=') || suffix().isEmpty()) return;
        const int cursor = lineEdit()->cursorPosition();
        const QString typed = text.endsWith(suffix()) ? text.chopped(suffix().size()) : text;
        showUnit(false);
        lineEdit()->setText(typed);
        lineEdit()->setCursorPosition(std::min(cursor, int(typed.size())));
        lineEdit()->setModified(true);
    });
    // The wheel changes a value only in the field being edited: over any
    // other field it scrolls the panel (a short Properties panel is scrolled
    // past a dozen fields).
    setFocusPolicy(Qt::StrongFocus);
}

void QuantityEdit::stepBy(int steps)
{
    stepping_ = true;
    QDoubleSpinBox::stepBy(steps);
    stepping_ = false;
}

// Text that reads as no number never reaches editingFinished (the line
// edit's validator holds it back) and the spin box then quietly puts the old
// value back: say why first, on Enter and on leaving the field.
QString QuantityEdit::typedExpression() const
{
    QString t = lineEdit()->text().trimmed();
    if (!unitText().isEmpty() && t.endsWith(" " + unitText())) t.chop(unitText().size() + 1);
    if (t.startsWith('=')) return t.mid(1).trimmed();
    // A parameter's name typed without the '=' ("thickness / 2", as other
    // CAD programs take it): the same expression, where the text reads as
    // no number. (A newcomer typed it so and was told "'top_t' is not a
    // number or a unit".) Units never count: "18mm" reads as a number first.
    if (!names_ || evaluate(lineEdit()->text()).value) return {};
    const QStringList names = names_();
    static const QRegularExpression word(QStringLiteral("[A-Za-z_][A-Za-z0-9_]*"));
    for (auto it = word.globalMatch(t); it.hasNext();)
        if (names.contains(it.next().captured())) return t;
    return {};
}

void QuantityEdit::setExpression(const QString& expression)
{
    expression_ = expression;
    if (hasFocus() && !lineEdit()->isModified()) showEnteredText();
}

void QuantityEdit::showDocument(double v, const QString& expression)
{
    showValue(v);
    expression_ = expression;
    if (hasFocus()) {
        showEnteredText();
        lineEdit()->setModified(false);
    }
}

void QuantityEdit::showEnteredText()
{
    if (expression_.isEmpty()) {
        showUnit(true);
        lineEdit()->setText(textFromValue(value()) + suffix());
        return;
    }
    // The spin box's validator appends the suffix to any text that lacks it:
    // an expression showed as "=depth - 2 mm", read as a length times a unit.
    showUnit(false);
    lineEdit()->setText("=" + expression_);
}

void QuantityEdit::showUnit(bool on)
{
    const QString wanted = on ? unitSuffix() : QString();
    if (suffix() != wanted) setSuffix(wanted);
}

void QuantityEdit::completeNames(std::function<QStringList()> names)
{
    names_ = names;
    new NameCompleter(lineEdit(), std::move(names), /*onlyAfterEquals=*/true);
}

void QuantityEdit::focusInEvent(QFocusEvent* event)
{
    QDoubleSpinBox::focusInEvent(event);
    // Only focus that enters the field shows the expression to edit,
    // selected. Focus back from a popup (the name completer's list closing
    // as a name is typed out) leaves the typing be: a newcomer's "=thic"
    // became the document's "=thickness", selected, and the next key "+"
    // replaced it all, which entered as the number 3.
    if (event->reason() == Qt::PopupFocusReason || lineEdit()->isModified()) return;
    if (!expression_.isEmpty()) {
        showEnteredText();
        lineEdit()->selectAll();
    }
}

bool QuantityEdit::inInches() const
{
    return unit_ == Unit::Length && LengthDisplay::instance().unit() == LengthUnit::Inches;
}

void QuantityEdit::followLengthDisplay()
{
    // A sixteenth of an inch per arrow step in inches, a millimetre otherwise.
    setSingleStep(inInches() ? 25.4 / 16.0 : 1.0);
    if (hasFocus() && !expression_.isEmpty()) return; // an expression shown has no unit to change
    setSuffix(unitSuffix()); // and the text again, in the unit now shown
    if (!hasFocus() || !lineEdit()->isModified()) showValue(value());
}

ExpressionResult QuantityEdit::evaluate(const QString& text) const
{
    if (unit_ == Unit::Length) return evaluateLength(text.toStdString(), LengthDisplay::instance().unit());
    return evaluateExpression(text.toStdString(), unitText().toStdString());
}

void QuantityEdit::reportUnreadableText()
{
    const QString text = lineEdit()->text();
    const ExpressionResult r = evaluate(text);
    if (!r.value) emit unreadable(QString::fromStdString(r.error)); // names the text ("cannot read 'twelve' ...")
}

void QuantityEdit::keyPressEvent(QKeyEvent* event)
{
    // Esc takes back what was typed and not entered, as in a table's cell;
    // a field left as it was passes Esc on (a dialog closes).
    if (event->key() == Qt::Key_Escape && lineEdit()->isModified()) {
        showEnteredText();
        lineEdit()->setModified(false);
        lineEdit()->selectAll();
        event->accept();
        emit reverted();
        return;
    }
    if (event->key() == Qt::Key_Escape) emit reverted(); // and on: a dialog closes
    if (event->key() == Qt::Key_Return || event->key() == Qt::Key_Enter) {
        // "=thickness + 2": an expression for the document, not a number for the box.
        if (const QString e = typedExpression(); !e.isNull()) {
            lineEdit()->setModified(false);
            emit expressionEntered(e);
            event->accept();
            return;
        }
        reportUnreadableText();
    }
    QDoubleSpinBox::keyPressEvent(event);
}

void QuantityEdit::focusOutEvent(QFocusEvent* event)
{
    // A popup (the names' completer, a context menu) is not leaving the
    // field: the spin box would read the unfinished text and put the value back.
    if (event->reason() == Qt::PopupFocusReason) {
        event->accept();
        return;
    }
    if (lineEdit()->isModified()) {
        if (const QString e = typedExpression(); !e.isNull()) {
            lineEdit()->setModified(false);
            emit expressionEntered(e);
        } else {
            reportUnreadableText();
        }
    }
    QDoubleSpinBox::focusOutEvent(event);
    showUnit(true); // the value again, with its unit
}

void QuantityEdit::wheelEvent(QWheelEvent* event)
{
    if (!hasFocus()) {
        event->ignore(); // to the scroll area around
        return;
    }
    QDoubleSpinBox::wheelEvent(event);
}

QString QuantityEdit::unitSuffix() const { return unitText().isEmpty() ? QString() : " " + unitText(); }

QString QuantityEdit::unitText() const
{
    switch (unit_) {
    case Unit::Length: return inInches() ? QString() : QStringLiteral("mm"); // inches: '"' is part of the number's text
    case Unit::Millimetres: return QStringLiteral("mm");
    case Unit::Degrees: return QStringLiteral("°");
    case Unit::None: return {};
    }
    return {};
}

bool QuantityEdit::beingEdited() const { return hasFocus() && lineEdit()->isModified(); }

void QuantityEdit::showValue(double v)
{
    const QSignalBlocker block(this);
    setValue(v);
}

QValidator::State QuantityEdit::validate(QString& text, int&) const
{
    // Anything may be on its way to an expression; only what reads as a
    // number is acceptable ("=..." is the document's: never a number here).
    if (text.trimmed().startsWith('=')) return QValidator::Intermediate;
    return evaluate(text).value ? QValidator::Acceptable : QValidator::Intermediate;
}

double QuantityEdit::valueFromText(const QString& text) const { return evaluate(text).value.value_or(value()); }

QString QuantityEdit::textFromValue(double v) const
{
    // Up to six decimals, without trailing zeros: 18, 2.5, 0.001; in inches
    // 11 3/4" or 0.708661" (LengthFormat.hpp: read back as the same length).
    return QString::fromStdString(lengthForEditing(v, inInches() ? LengthUnit::Inches : LengthUnit::Millimetres));
}

void QuantityEdit::fixup(QString& input) const { input = textFromValue(value()) + suffix(); }

} // namespace kerf::ui
