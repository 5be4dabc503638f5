# 集线器的拒绝信息，以控制台的语言显示（crates/hub/console/api.js refusalWords）。

## 集线器的拒绝信息，以控制台的语言显示；集线器自己的说明（字段或对象）在有用时以英文附上。

api-error-400 = 集线器没有接受此内容。
api-error-401 = 未登录，或电子邮件或密码错误。
api-error-403 = 只有诊所管理员可以执行此操作。
api-error-404 = 未找到，可能已被删除。
api-error-409 = 这与集线器中保存的内容冲突。
api-error-413 = 内容太大，集线器无法接收。
api-error-415 = 集线器无法理解此请求。
api-error-422 = 已拒绝：超出允许的数值或安全范围。
api-error-429 = 尝试次数过多。请在 { $seconds } 秒后重试。
api-error-503 = 集线器正忙。请在 { $seconds } 秒后重试。
api-error-other = 集线器出了问题，详情见其日志。

## 集线器拒绝的原因，按其代码（crates/hub-store/src/refusal.rs）：每条一句简单的话。
## $field 和 $what 已是控制台的用词。

api-why-field-refused = 集线器没有接受「{ $field }」。
api-why-empty = 「{ $field }」是空的。请写几个字。
api-why-too-long = 「{ $field }」太长：最多 { $max } 个字符。
api-why-control-characters = 「{ $field }」含有隐藏的控制字符。请只用普通文字。
api-why-missing = 缺少「{ $field }」。
api-why-not-one-of = 「{ $field }」不是可选的值之一。
api-why-out-of-range = 「{ $field }」必须在 { $min } 到 { $max } 之间。
api-why-bad-date = 「{ $field }」不是有效的日期。请写成 年-月-日。
api-why-future-date = 「{ $field }」是将来的日期。请选择发生的那一天。
api-why-bad-id = 地址中的「{ $field }」编号不可能存在。
api-why-bad-email = 这不是电子邮件地址。格式像 name@clinic.cn。
api-why-bad-pseudonym = 最多 { $max } 个字母、数字、点、连字符或下划线。不要用真实姓名。
api-why-password-invisible = 密码含有看不见的字符。请只输入看得见的字符。
api-why-password-length = 密码至少需要 { $min } 个字符。
api-why-password-spaces = 密码几乎全是空格。
api-why-password-email = 密码不能是您的电子邮件地址。
api-why-password-common = 这是最常见的密码之一。请换一个。
api-why-password-repeated = 密码在重复自己。请至少使用 { $min } 个不同的字符。
api-why-password-sequence = 密码是 abcdef 或 123456 这样的连续序列。请换一个。
api-why-password-guessable = 密码太容易被猜到。几个互不相关的词就很好。
api-why-password-same = 新密码必须与当前密码不同。
api-why-snooze-past = 暂缓必须在将来结束。请选择更晚的日期。
api-why-not-found = 找不到这个{ $what }。它可能已被删除。
api-why-already-exists = 这个{ $what }已经存在。请换一个。
api-why-no-endpoint = 集线器没有这个页面。
api-why-login-refused = 电子邮件或密码错误。
api-why-log-in-first = 请先登录。
api-why-one-time-password = 请先更改您的一次性密码。
api-why-admin-only = 只有诊所管理员可以这样做。
api-why-own-care-only = 您只能把患者加入自己的照护。管理员可以选择其他治疗师。
api-why-no-therapist-email = 没有治疗师使用这个电子邮件地址。
api-why-throttled = 尝试次数太多。请在 { $seconds } 秒后再试。
api-why-alert-gone = 这条提醒已经解除。请重新加载患者列表。
api-why-alert-changed = 显示这条提醒后又发生了新情况。请再看一次。没有保存任何内容。
api-why-regimen-shape = 集线器无法读取这份处方。
api-why-regimen-text = 处方文本第 { $line } 行有错误。
api-why-regimen-unreadable = 无法读取处方文本。
api-why-regimen-exercise = 第 { $exercise } 个练习有数值超出允许范围。
api-why-above-wheel = 第 { $exercise } 个练习要求的力超过了该患者方向盘的能力：最多 { $max_nm } N·m。
api-why-recording-not-arrived = 这次训练的记录还没有完整到达。
api-why-recording-unreadable = 集线器无法读取这次训练的记录。
api-why-recording-too-large = 这份记录有 { $mb } MB。集线器最多回放 { $max_mb } MB。
api-why-replay-pending = 您上一次的回放还在准备中。请等它显示出来。
api-why-replay-busy = 集线器正忙于其他回放。请稍后再试。
api-why-live-streams = 同时最多 { $max } 个实时查看。请先关闭一个。
api-why-unknown-language = 控制台没有这种语言的文字。
api-why-unknown-time-zone = 集线器不认识这个时区。
api-why-body-malformed = 集线器无法读取这个请求。
api-why-body-too-large = 这对集线器来说太大了。
api-why-body-not-json = 集线器不理解这个请求。
api-why-internal = 集线器出了问题。详情见其日志。

## 拒绝中提到的字段和事物。

api-field-text = 文字
api-field-note = 备注
api-field-password = 密码
api-field-email = 电子邮件地址
api-field-pseudonym = 化名
api-field-snooze-until-ms = 暂缓结束时间
api-field-setting = 设置
api-field-scale = 量表
api-field-assessed-on = 评估日期
api-field-score = 分数
api-field-affected-blocks-per-min = 患侧每分钟方块数
api-field-unaffected-blocks-per-min = 健侧每分钟方块数
api-field-sort = 排序
api-field-alert = 提醒
api-field-query = 搜索
api-field-key = 提醒
api-field-regimen = 处方
api-field-path = 地址
api-field-patient-id = 患者
api-field-session-id = 训练
api-field-station-id = 训练站
api-field-scale-id = 评估
api-thing-patient = 患者
api-thing-station = 训练站
api-thing-session = 训练
api-thing-therapist = 治疗师
api-thing-scale = 评估
api-thing-pseudonym = 化名
api-thing-email = 电子邮件地址
api-thing-clinical-scale = 评估
api-thing-station-or-certificate = 训练站
