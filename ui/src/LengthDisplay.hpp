#pragma once
// The user's choice of how the part's lengths are shown: millimetres, or
// inches and fractions of an inch (View > Lengths). Remembered between
// sessions. Display only: the document keeps millimetres, and the
// modelling accuracies (feature size, export tolerance) stay in millimetres
// (a 64th of an inch is 0.4 mm; they are set in hundredths).

#include "kerf/document/LengthFormat.hpp"

#include <QObject>
#include <QString>

namespace kerf::ui {

class LengthDisplay : public QObject {
    Q_OBJECT
public:
    /// The one for the application (read from the settings the first time).
    static LengthDisplay& instance();

    LengthUnit unit() const { return unit_; }
    /// Chosen by the user: remembered, and every length shown follows.
    void setUnit(LengthUnit unit);

    /// "32.00 mm", or "1 1/4\"" / "≈ 1 17/64\"".
    QString readout(double mm, int mmDecimals = 2) const;
    /// For lists of lengths that name the unit once ("18.00 x 300.00 mm"):
    /// "18.00" or "≈ 45/64\"" (inches carry their mark each), and the
    /// suffix, " mm" or nothing.
    QString bare(double mm) const;
    QString suffix() const;

signals:
    void changed();

private:
    LengthDisplay();
    LengthUnit unit_ = LengthUnit::Millimetres;
};

} // namespace kerf::ui
