#include "JobStatusBar.h"

#include <QHBoxLayout>
#include <QProgressBar>
#include <QStatusBar>
#include <QToolButton>
#include <algorithm>
#include <cmath>

#include "JobRunner.h"

namespace aero::ui {

JobStatusBar::JobStatusBar(JobRunner* jobs, QStatusBar* bar, QWidget* parent) : QWidget(parent), jobs_(jobs), bar_(bar) {
    setObjectName(QStringLiteral("jobStatusBar"));
    layout_ = new QHBoxLayout(this);
    layout_->setContentsMargins(0, 0, 0, 0);
    layout_->setSpacing(6);
    hide();
    connect(jobs_, &JobRunner::jobStarted, this, &JobStatusBar::add);
    connect(jobs_, &JobRunner::jobFinished, this, &JobStatusBar::remove);
    for (Job* job : jobs_->jobs()) add(job);
}

void JobStatusBar::add(Job* job) {
    auto* item = new QWidget(this);
    auto* row = new QHBoxLayout(item);
    row->setContentsMargins(0, 0, 0, 0);
    row->setSpacing(2);
    auto* progress = new QProgressBar(item);
    progress->setObjectName(QStringLiteral("jobProgress"));
    progress->setMaximumWidth(170);
    progress->setRange(0, 0);  // busy until the job says how far it is
    progress->setFormat(job->title());
    progress->setTextVisible(true);
    progress->setToolTip(job->title());
    auto* cancel = new QToolButton(item);
    cancel->setObjectName(QStringLiteral("jobCancel"));
    cancel->setText(tr("Cancel"));
    cancel->setToolTip(tr("Cancel %1").arg(job->title()));
    row->addWidget(progress);
    row->addWidget(cancel);
    layout_->addWidget(item);
    items_.insert(job->id(), item);
    show();
    connect(cancel, &QToolButton::clicked, job, &Job::cancel);
    connect(job, &Job::progressed, item, [this, progress, job](double fraction, const QString& text) {
        if (fraction >= 0) {
            progress->setRange(0, 100);
            progress->setValue(static_cast<int>(std::lround(100 * std::min(1.0, fraction))));
            progress->setFormat(job->title() + QStringLiteral(" %p%"));
        }
        if (!text.isEmpty()) {
            progress->setToolTip(text);
            bar_->showMessage(text);
        }
    });
    bar_->showMessage(job->title());
}

void JobStatusBar::remove(Job* job) {
    if (QWidget* item = items_.take(job->id())) item->deleteLater();
    if (items_.isEmpty()) hide();
    switch (job->state()) {
        case Job::State::Finished:
            bar_->showMessage(tr("%1: done").arg(job->title()), 8000);
            break;
        case Job::State::Cancelled:
            bar_->showMessage(tr("%1: cancelled").arg(job->title()), 8000);
            break;
        case Job::State::Failed:
            bar_->showMessage(tr("%1 failed: %2").arg(job->title(), job->error()), 8000);
            break;
        case Job::State::Running:
            break;
    }
}

}  // namespace aero::ui
