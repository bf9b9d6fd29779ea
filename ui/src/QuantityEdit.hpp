#pragma once
// A numeric field with a unit ("mm", inches, "°" or none) that takes
// arithmetic ("18*2", "450 - 2*18", "11 3/4"), steps with the arrows and
// (once clicked into) the wheel, and reports
// text it cannot read instead of silently dropping it. A spin box, so a
// value dragged with the arrows or the wheel arrives as a stream of
// valueChanged() (merged into one undo step by the editor).

#include "Expression.hpp"

#include <QDoubleSpinBox>
#include <QStringList>

#include <functional>

namespace kerf::ui {

class QuantityEdit : public QDoubleSpinBox {
    Q_OBJECT
public:
    /// Length: a length of the part, shown in the user's unit (LengthDisplay);
    /// Millimetres: an accuracy (feature size, tolerance), always in millimetres.
    enum class Unit { Length, Millimetres, Degrees, None };
    explicit QuantityEdit(Unit unit, QWidget* parent = nullptr);
    Unit unit() const { return unit_; }

    /// Shows `v` without emitting valueChanged (a refresh from the document).
    void showValue(double v);
    /// Text typed and not yet entered is in the field (a refresh leaves it be).
    bool beingEdited() const;
    /// The expression that drives the value ("" when none): shown as
    /// "=expression" while the field has the focus, to be edited there.
    void setExpression(const QString& expression);
    /// The document's value and expression again after a refused entry:
    /// what the field showed before the text typed ("=leg" while it has
    /// the focus, where a refused -5 over it left the number "40 mm").
    void showDocument(double v, const QString& expression);
    /// Offers `names` (asked each time) as an expression is typed after '=';
    /// text that reads as no number but uses one of them is an expression
    /// too, without the '=' ("thickness / 2").
    void completeNames(std::function<QStringList()> names);

    /// Inside a step of the arrows, the wheel or Page Up/Down: the change
    /// valueChanged reports is a step (merged into one undo step with the
    /// next ones), not a value typed and entered (a step of its own).
    bool stepping() const { return stepping_; }
    void stepBy(int steps) override;

    QValidator::State validate(QString& text, int& pos) const override;
    double valueFromText(const QString& text) const override;
    QString textFromValue(double value) const override;
    void fixup(QString& input) const override;

protected:
    void wheelEvent(QWheelEvent* event) override;
    void focusInEvent(QFocusEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;
    void focusOutEvent(QFocusEvent* event) override;

signals:
    /// The text typed could not be read as a number (the reason).
    void unreadable(const QString& reason);
    /// "=..." (or text using a name of completeNames) was typed and entered
    /// (Enter, or leaving the field): the expression, without the '=' and
    /// the field's unit.
    void expressionEntered(const QString& expression);
    /// Esc took back the text typed: the field shows what was entered last.
    void reverted();

private:
    bool stepping_ = false;
    /// Lengths shown in inches in this field.
    bool inInches() const;
    /// Unit, step and text for the length unit now shown.
    void followLengthDisplay();
    ExpressionResult evaluate(const QString& text) const;
    QString unitText() const;
    QString unitSuffix() const; // " mm", " °" or none
    /// The typed text as an expression ("=...", or using a name), or a null string.
    QString typedExpression() const;
    QString expression_;
    std::function<QStringList()> names_; // the names an expression may use (completeNames)
    void reportUnreadableText();
    /// What was last entered: the expression ("=depth - 2", without the
    /// unit), else the value with its unit.
    void showEnteredText();
    /// The unit after the value, or none while an expression is shown.
    void showUnit(bool on);
    Unit unit_;
};

} // namespace kerf::ui
