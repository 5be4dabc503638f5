# 患者的“进展”标签页。

progress-list-separator = {"、"}
progress-percent = { $n } %

## 疼痛、依从性和提醒

progress-summary-title = 疼痛、依从性和提醒
progress-pain-title = 疼痛
progress-pain-latest = 疼痛 { $pain }/10
progress-pain-after = （{ $at } 的训练后）。
progress-pain-before = 之前：{ $list }（最新的在前）。
progress-pain-none = 还没有疼痛回答。
progress-pain-chart-label = 每次训练后的疼痛，0 到 10：数字见训练列表
progress-pain-axis = 疼痛（0–10）
progress-checkin-pain = 疼痛 { $pain }/10
progress-checkin-effort = 用力程度 { $effort }/10
progress-checkin-skipped = 已跳过
progress-felt = 感觉{ $felt }
progress-felt-too-easy = 太容易
progress-felt-about-right = 刚好
progress-felt-too-hard = 太难
progress-after-last = 上次训练后：{ $answers }。
progress-adherence-title = 依从性
progress-week = 最近 7 天：{ $sessionsPrescribed ->
        [none] { $sessions } 次训练
       *[other] 处方 { $sessionsPrescribed } 次中完成 { $sessions } 次
    }，{ $minutesPrescribed ->
        [none] 活动 { $minutes } 分钟
       *[other] 处方活动 { $minutesPrescribed } 分钟中完成 { $minutes } 分钟
    }。
progress-week-repetitions = 最近 7 天的重复次数：{ $repetitions }。
progress-stopped-early = 提前结束：最近 { $count } 次训练中有 { $stopped } 次。
progress-alerts-title = 提醒
progress-alerts-none = 没有提醒。

## 训练量：按周和按天的主动训练时间与重复次数

progress-dose-title = 训练量：训练时间与重复次数
progress-dose-explain = 主动训练时间不包括暂停和休息。重复次数是方向盘的动作次数。每周与当前处方比较。
progress-dose-weeks-caption = { $weeks ->
        [one] 按周：最近 7 天
       *[other] 按周，最近 { $weeks } 周
    }
progress-dose-days-caption = 按天，最近 7 天
progress-dose-col-week = 周
progress-dose-col-day = 日期
progress-dose-col-sessions = 训练次数
progress-dose-col-active = 主动训练
progress-dose-col-repetitions = 重复次数
progress-dose-week-range = { $from } 至 { $to }
progress-dose-below = 低于处方

## 最近一次训练与之前的比较

progress-latest-title = 练习：最近一次训练与之前的比较
progress-latest-title-kind = 练习：最近一次{ $kind }训练与之前的比较
progress-compared = { $early ->
        [included] 最近一次结束的训练（按处方完成或提前结束）（{ $session }）与患者基线（前 { $baseline } 次{ $kind }训练的平均值）比较，趋势与之前最多 { $earlier } 次{ $kind }训练比较；在指标测量误差范围内的变化显示为“稳定”。已包括提前结束的训练。
       *[left-out] 最近一次按处方完成的训练（{ $session }）与患者基线（前 { $baseline } 次{ $kind }训练的平均值）比较，趋势与之前最多 { $earlier } 次{ $kind }训练比较；在指标测量误差范围内的变化显示为“稳定”。提前结束的训练列在下方，不参与比较。
    }
progress-compared-none = 还没有按处方完成的训练：无可比较。
progress-col-measure = 指标
progress-col-latest = 最近
progress-col-baseline = 基线
progress-col-trend = 趋势
progress-against-prescription = 与处方比较，不是趋势
progress-include-early = 包括提前结束的训练
progress-include-early-none = 包括提前结束的训练（没有）

## 各类练习

progress-kind-title = { $kind }训练（{ $count }）
progress-kind-latest = ：最近 { $list }
progress-headline-item = { $measure } { $value }
progress-kind-note = { $names }。每个指标一张图，每次训练一格，最早的在左边。
progress-kind-hollow = 空心点：{ $count } 次训练提前结束（{ $early ->
        [included] 已包括
       *[left-out] 未连入折线
    }）。
progress-kind-no-measures = 这些训练没有记录指标。
progress-prescribed-time = 处方时间（{ $unit }）
progress-noise-band = 阴影带是基线周围的测量误差：落在其中的点不算变化。
progress-chart-label = 每次训练的{ $measure }：数字见下表

## 难度

progress-difficulty-title = 随患者调整的难度
progress-difficulty-now = ：当前 { $now }（0 最容易，1 为处方难度）
progress-difficulty-explain = 0：处方速度和形状的一半，并提供全部辅助；1：按处方执行的训练方案。由训练站在方案范围内设定。
progress-difficulty-axis = 难度（0–1）
progress-difficulty-why-adapt-off = 自适应已关闭：按治疗师的设置。
progress-difficulty-why-first-start = 第一次训练：治疗师设定的起点。
progress-difficulty-why-first-midway = 第一次训练：取治疗师设定范围的中间值。
progress-difficulty-why-success-above = 成功率 { $success }% 高于 { $target }% 的目标。
progress-difficulty-why-success-below = 成功率 { $success }% 低于 { $target }% 的目标。
progress-difficulty-why-success-at = 成功率 { $success }% 正好达到 { $target }% 的目标。
progress-difficulty-why-no-rate = 上次训练没有成功率：保持不变。
progress-difficulty-why-felt-too-hard = 患者说太难了。
progress-difficulty-why-felt-too-easy = 患者说太容易了。
progress-difficulty-held-highest = 保持在治疗师设定的最高值。
progress-difficulty-held-lowest = 保持在治疗师设定的最低值。
progress-numbers-caption = 图中的数字，最新的在前
progress-col-started = 开始时间
progress-col-difficulty = 难度
progress-col-change = 变化
progress-col-success = 成功率
progress-col-why = 原因

## 技术名称

progress-technical-summary = 详情：这些指标的技术名称
progress-technical-caption = 即电子表格第二行表头和 FHIR 导出中使用的名称
progress-col-data-name = 数据中的名称
progress-col-technical = 技术名称

progress-definitions-summary = 每项指标测量什么及其来源
progress-col-definition = 定义
progress-col-source = 来源

## 训练列表和打印

progress-sessions-title = 训练（{ $count }）
progress-col-exercise = 练习
progress-col-ended = 结束方式
progress-col-checkin = 患者的回答
progress-col-results = 结果和录制
progress-col-notes = 治疗师备注
progress-each-exercise = 各项练习
progress-replay = 回放
progress-note-session = { $at } 的训练
progress-range = 训练日期：{ $from } 至 { $to }
progress-range-none = 还没有训练
progress-zone-utc = 时间为 UTC
progress-zone = 时间为 { $zone } 和 UTC
progress-clinic-unnamed = 未设置诊所名称
progress-print-of = { $name } 的进展
progress-printed = 打印于 { $day }
progress-print = 打印一页摘要
progress-download = 下载电子表格（CSV；{ $zone }）
progress-download-assessments = 下载标准评估（CSV；{ $zone }）
progress-scales-failed = 无法显示临床量表：{ $error }

## 标准评估（issue 42）：每次都是同样的简短测试，放在页面最前面

progress-assessment-title = 标准评估
progress-assessment-intro = 每次都是同样的简短测试，方向盘不提供帮助（协议 { $protocol }）。最新的在前。它与练习及其趋势分开。
progress-assessment-none = 还没有标准评估。如需安排，请在训练方案中设定间隔天数。
progress-assessment-col-measure = 部分与指标
progress-assessment-row = { $part }：{ $measure }
progress-assessment-part-range = 主动活动范围
progress-assessment-part-tracking-slow = 跟踪，慢速
progress-assessment-part-tracking-medium = 跟踪，中速
progress-assessment-part-tracking-fast = 跟踪，快速
progress-assessment-part-steps = 跳动
progress-assessment-part-strength = 力量

## 区分真实变化与测量噪声（issue 42）：最新一次评估与第一次相比

progress-assessment-col-change = 与第一次相比的变化（{ $day }）
progress-assessment-col-change-none = 与第一次相比的变化
progress-assessment-band = ± { $band }（{ $source }）
progress-assessment-verdict-better = 变好
progress-assessment-verdict-worse = 变差
progress-assessment-verdict-changed = 有变化（没有哪个方向更好）
progress-assessment-verdict-within-noise = 在测量噪声范围内
progress-assessment-verdict-no-noise-figure = 尚无噪声数值，因此不作判断
progress-assessment-source-own = 噪声范围来自患者本人的 { $repeats } 次评估
progress-assessment-source-cohort = 噪声范围来自做同一测试的模拟患者
progress-assessment-source-published = 噪声范围来自已发表的研究
progress-assessment-source-short-own = 本人
progress-assessment-source-short-cohort = 队列
progress-assessment-source-short-published = 研究
progress-assessment-change-sr = 与第一次评估相比的变化：{ $change }。噪声范围为正负 { $band }（{ $source }）。判断：{ $verdict }。
progress-assessment-change-sr-none = 与第一次评估相比的变化：{ $change }。尚无噪声数值，因此不作判断。
progress-assessment-change-none = 目前只有一次评估：还没有可比较的。
progress-assessment-change-missing = 无变化可显示：最新或第一次评估中缺少该测量值。
progress-assessment-noise-note = 只有当变化大于测量噪声（± 最小真实变化，MDC95）时才判断变好或变差。从第 6 次评估起，噪声范围取自患者本人（本人）；在此之前取自模拟患者（队列）或已发表的研究（研究）。
