# FHIR 导出的叙述文字（crates/hub-care/src/fhir/narrative.rs）。

fhir-patient = 患者 { $pseudonym }。只导出诊所的化名。
fhir-regimen = 居家训练方案，第 { $version } 版，开具于 { $day }。
fhir-request = 在家使用远程康复站进行运动治疗：{ $exercises } 项练习。
fhir-request-week = 每周 { $sessions } 次，每次约 { $minutes } 分钟。
fhir-session = { $start }（UTC）的训练：{ $exercise }。
fhir-session-open = 导出此记录时，训练尚未结束。
fhir-duration = { $start }（UTC）训练的运动时间：{ $minutes } 分钟。
fhir-measure = 测量项
fhir-value = 数值
fhir-scale = { $day } 的 { $scale }：{ $value }。
fhir-code-system = { $title }：{ $count } 个代码，每个都有定义和单位。
fhir-questionnaire = 患者每次训练后在康复站上回答的问题。
fhir-checkin = { $start }（UTC）训练后的反馈。
fhir-answer-skipped = 已跳过
fhir-answer-score = { $value } / 10
fhir-device = 远程康复站 { $station }，软件 { $version }：力反馈方向盘和手臂传感器。
fhir-therapist = 诊所的治疗师（{ $id }）。

# 标准评估（crates/hub-care/src/fhir/assessment.rs）。
fhir-assessment-title = 方向盘标准评估
fhir-assessment = { $start }（UTC）的标准评估，协议第 { $protocol } 版，目标跳动由种子 { $seed } 生成。包括：{ $parts }。
fhir-assessment-part = { $part }：{ $start }（UTC）标准评估的一部分，协议第 { $protocol } 版。
fhir-assessment-method = 标准评估，协议第 { $protocol } 版，目标跳动由种子 { $seed } 生成
# 代码旁的简短文字。
fhir-session-text = 远程康复训练：{ $exercise }
fhir-regimen-title = 居家训练方案，第 { $version } 版
fhir-request-text = { $title }：在远程康复站上的 { $exercises } 项练习
fhir-device-type = 居家康复站：力反馈方向盘和手臂传感器
