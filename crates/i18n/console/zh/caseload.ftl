# 患者列表（#/patients）：谁最需要关注、本周训练、趋势、确认提醒、疼痛停训后允许再次训练。

caseload-title = 患者
caseload-order = 排序
caseload-order-need = 最需要关注的在前
caseload-order-last-session = 最久未训练的在前
caseload-order-pseudonym = 按化名
caseload-show = 显示
caseload-show-all = 全部患者
caseload-show-only = 仅：{ $kind }
caseload-mine = 仅我的患者
caseload-caption-need = 您的患者，最需要关注的在前。打开患者可查看正在进行的训练、查看进展或开具处方。
caseload-caption-chosen = 您的患者，按所选顺序。打开患者可查看正在进行的训练、查看进展或开具处方。
caseload-col-patient = 患者
caseload-col-needs = 需要关注
caseload-col-last-session = 上次训练
caseload-col-last-7-days = 最近 7 天
caseload-col-trend = 趋势
caseload-none = 还没有患者。
caseload-none-with-alert = 目前没有患者有此提醒。
caseload-add-patient = 添加患者
caseload-add-patient-note = （并打印配对单）
caseload-thresholds-link = 提醒阈值
caseload-nothing-needed = 无需关注
caseload-more = 另有 { $count } 条
caseload-acknowledged = 已确认 { $count } 条提醒
caseload-week = { $sessionsPrescribed ->
        [none] { $sessions } 次训练
       *[other] 处方 { $sessionsPrescribed } 次中完成 { $sessions } 次
    }，{ $minutesPrescribed ->
        [none] 活动 { $minutes } 分钟
       *[other] 处方活动 { $minutesPrescribed } 分钟中完成 { $minutes } 分钟
    }
# The week's repetitions (wheel movements) in the caseload's week column.
caseload-repetitions = { $repetitions } 次重复
caseload-trend-kind = { $kind }训练：
caseload-trend-pct-in-lane = 车道内时间
caseload-trend-wheel-rom-deg = 方向盘转动范围
caseload-trend-sparc-median = 流畅度
caseload-trend-better = 改善
caseload-trend-worse = 变差
caseload-trend-steady = 稳定
caseload-acknowledge = 确认
caseload-quiet-former = 一位已离开诊所的治疗师
caseload-quiet-snoozed = 由 { $who } 于 { $at } 暂缓至 { $until }：{ $note }
caseload-quiet-acknowledged = 由 { $who } 于 { $at } 确认（有新情况前不再提醒）：{ $note }

## 确认提醒

caseload-ack-legend = 暂不提醒
caseload-ack-until-new = 直到出现新情况
caseload-ack-until-day = 直到某一天：
caseload-ack-snooze-until = 暂缓至
caseload-ack-note = 备注
caseload-ack-note-hint = （做了什么，例如“已致电：正在休息，周一看全科医生”）
caseload-ack-no-day = 请选择提醒可以再次出现的日期。
caseload-save = 保存
caseload-cancel = 取消

## 疼痛停训后允许再次训练

caseload-allow-training = 允许今天训练
caseload-allow-question = 尽管患者报告了疼痛，仍允许今天再次训练吗？
caseload-allow-explain = 训练站在这次疼痛回答后停止了今天的训练。如果您已与患者沟通且训练是安全的，训练站将允许其今天再次训练。此操作会记入审计日志。
caseload-allow-confirm = 是，允许今天训练
caseload-allow-done = 已再次允许训练（{ $at }）。训练站会立即收到，或在下次连接时收到。
caseload-training-allowed = 已于 { $at } 再次允许训练。
