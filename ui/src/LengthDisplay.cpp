#include "LengthDisplay.hpp"

#include <QSettings>

namespace kerf::ui {

namespace {
const char* const kSettingsKey = "view/lengthUnit";
}

LengthDisplay::LengthDisplay()
{
    const std::string key = QSettings().value(kSettingsKey, "mm").toString().toStdString();
    unit_ = lengthUnitFromKey(key).value_or(LengthUnit::Millimetres);
}

LengthDisplay& LengthDisplay::instance()
{
    static LengthDisplay display;
    return display;
}

void LengthDisplay::setUnit(LengthUnit unit)
{
    if (unit == unit_) return;
    unit_ = unit;
    QSettings().setValue(kSettingsKey, QString::fromUtf8(lengthUnitKey(unit).data(), qsizetype(lengthUnitKey(unit).size())));
    emit changed();
}

QString LengthDisplay::readout(double mm, int mmDecimals) const
{
    return QString::fromStdString(lengthReadout(mm, unit_, mmDecimals));
}

QString LengthDisplay::bare(double mm) const
{
    QString s = readout(mm);
    if (unit_ == LengthUnit::Millimetres) s.chop(3); // " mm"
    return s;
}

QString LengthDisplay::suffix() const { return unit_ == LengthUnit::Millimetres ? QStringLiteral(" mm") : QString(); }

} // namespace kerf::ui
