#include "QuantityEdit.hpp"

#include "Expression.hpp"
#include "UndoKeysToWindow.hpp"

#include <QLineEdit>
#include <QSignalBlocker>
#include <QKeyEvent>
#include <QWheelEvent>

#include <cmath>

namespace kerf::ui {

QuantityEdit::QuantityEdit(Unit unit, QWidget* parent) : QDoubleSpinBox(parent), unit_(unit)
{
    // Wide ranges: the document's validation, not the widget, says what is
    // allowed, and says why.
    setRange(-1e9, 1e9);
    setDecimals(6);
    setSingleStep(unit == Unit::Degrees ? 1.0 : 1.0);
    setKeyboardTracking(false); // typed text commits on Enter or leaving the field
    setAccelerated(true);
    if (unit == Unit::Millimetres) setSuffix(QStringLiteral(" mm"));
    if (unit == Unit::Degrees) setSuffix(QStringLiteral(" °"));
    setCorrectionMode(QAbstractSpinBox::CorrectToPreviousValue);
    connect(lineEdit(), &QLineEdit::editingFinished, this, [this] {
        lineEdit()->setModified(false); // committed: Ctrl+Z now undoes the edit (UndoKeysToWindow)
    });
    UndoKeysToWindow::install(lineEdit(), this);
    // The wheel changes a value only in the field being edited: over any
    // other field it scrolls the panel (a short Properties panel is scrolled
    // past a dozen fields).
    setFocusPolicy(Qt::StrongFocus);
}

// Text that reads as no number never reaches editingFinished (the line
// edit's validator holds it back) and the spin box then quietly puts the old
// value back: say why first, on Enter and on leaving the field.
void QuantityEdit::reportUnreadableText()
{
    const QString text = lineEdit()->text();
    const ExpressionResult r = evaluateExpression(text.toStdString(), unitText().toStdString());
    if (!r.value) emit unreadable(QString::fromStdString(r.error)); // names the text ("cannot read 'twelve' ...")
}

void QuantityEdit::keyPressEvent(QKeyEvent* event)
{
    if (event->key() == Qt::Key_Return || event->key() == Qt::Key_Enter) reportUnreadableText();
    QDoubleSpinBox::keyPressEvent(event);
}

void QuantityEdit::focusOutEvent(QFocusEvent* event)
{
    if (lineEdit()->isModified()) reportUnreadableText();
    QDoubleSpinBox::focusOutEvent(event);
}

void QuantityEdit::wheelEvent(QWheelEvent* event)
{
    if (!hasFocus()) {
        event->ignore(); // to the scroll area around
        return;
    }
    QDoubleSpinBox::wheelEvent(event);
}

QString QuantityEdit::unitText() const
{
    switch (unit_) {
    case Unit::Millimetres: return QStringLiteral("mm");
    case Unit::Degrees: return QStringLiteral("°");
    case Unit::None: return {};
    }
    return {};
}

void QuantityEdit::showValue(double v)
{
    const QSignalBlocker block(this);
    setValue(v);
}

QValidator::State QuantityEdit::validate(QString& text, int&) const
{
    // Anything may be on its way to an expression; only what reads as a
    // number is acceptable.
    const ExpressionResult r = evaluateExpression(text.toStdString(), unitText().toStdString());
    return r.value ? QValidator::Acceptable : QValidator::Intermediate;
}

double QuantityEdit::valueFromText(const QString& text) const
{
    const ExpressionResult r = evaluateExpression(text.toStdString(), unitText().toStdString());
    return r.value.value_or(value());
}

QString QuantityEdit::textFromValue(double v) const
{
    // Up to six decimals, without trailing zeros: 18, 2.5, 0.001.
    QString s = QString::number(v, 'f', 6);
    if (s.contains('.')) {
        while (s.endsWith('0')) s.chop(1);
        if (s.endsWith('.')) s.chop(1);
    }
    if (s == "-0") s = "0";
    return s;
}

void QuantityEdit::fixup(QString& input) const { input = textFromValue(value()) + suffix(); }

} // namespace kerf::ui
